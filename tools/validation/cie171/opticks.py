"""Running Opticks: `opticks trace` and `opticks measure`, their CSVs read back."""
import pathlib
import subprocess
import time


def read_points(path):
    out = []
    for line in pathlib.Path(path).read_text().splitlines():
        line = line.split("#")[0].strip()
        if not line or line.startswith("x"):
            continue
        out.append([float(v) for v in line.replace(",", " ").split()])
    return out


def read_measure(path):
    """`opticks measure` CSV → list of dicts of floats."""
    lines = pathlib.Path(path).read_text().splitlines()
    head = lines[0].split(",")
    return [dict(zip(head, map(float, line.split(",")))) for line in lines[1:] if line.strip()]


class Opticks:
    def __init__(self, exe, work):
        self.exe = str(exe)
        self.work = work

    def run(self, args):
        t = time.perf_counter()
        subprocess.run([self.exe, *args], cwd=self.work, check=True, stdout=subprocess.DEVNULL)
        return time.perf_counter() - t

    def trace(self, scene, name, paths=None):
        args = ["trace", str(scene), "-o", f"{name}.opds", "--overwrite", "--quiet"]
        if paths:
            args += ["--paths", paths]
        return self.run(args)

    def measure_points(self, name, points, extra=()):
        t = self.run(["measure", f"{name}.opds", "--points", str(points), "-o", f"{name}.csv", "--quiet", *extra])
        return read_measure(self.work / f"{name}.csv"), t

    def measure_surface(self, name, surface, cells="1x1"):
        out = f"{name}-{surface}.csv"
        t = self.run(["measure", f"{name}.opds", "--surface", surface, "--cells", cells, "-o", out, "--quiet"])
        rows = read_measure(self.work / out)
        return (rows[0] if cells == "1x1" else rows), t

    def remove(self, name):
        (self.work / f"{name}.opds").unlink(missing_ok=True)
