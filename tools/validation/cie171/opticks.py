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


def read_meters(path):
    """The CSV of a `measure` run with several meters (its first column `meter`) → {meter: list of
    dicts of floats}; one meter's CSV (no `meter` column) → {None: its rows}."""
    lines = pathlib.Path(path).read_text().splitlines()
    head = lines[0].split(",")
    out = {}
    for line in lines[1:]:
        if not line.strip():
            continue
        fields = line.split(",")
        meter = fields.pop(0) if head[0] == "meter" else None
        out.setdefault(meter, []).append(dict(zip(head[1:] if meter is not None else head, map(float, fields))))
    return out


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

    def measure_surfaces(self, name, surfaces, cells="1x1"):
        """Every surface of `surfaces` in one `measure` run (one read of the dataset): (rows per
        surface, in their order, seconds)."""
        out = f"{name}-surfaces.csv"
        meters = [a for s in surfaces for a in ("--surface", s)]
        t = self.run(["measure", f"{name}.opds", *meters, "--cells", cells, "-o", out, "--quiet"])
        rows = read_meters(self.work / out)
        return [rows[s] for s in surfaces], t

    def remove(self, name):
        (self.work / f"{name}.opds").unlink(missing_ok=True)
