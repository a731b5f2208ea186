"""Running Radiance (pyradiance's oconv and rtrace) and the settings the report's columns use."""
import math
import os
import pathlib
import subprocess
import tempfile
import time

from .closed_forms import RADIANCE_EFFICACY


class Radiance:
    """pyradiance's oconv and rtrace; lux = 179 × (0.2651 R + 0.6701 G + 0.0648 B), and the
    scenes are grey, so lux = 179 × G."""

    def __init__(self):
        import pyradiance  # noqa: F401 (only to find the binaries)

        pkg = pathlib.Path(pyradiance.__file__).parent
        self.env = dict(os.environ, PATH=f"{pkg / 'bin'}:{os.environ['PATH']}", RAYPATH=f".:{pkg / 'lib'}")
        self.version = subprocess.run(["rtrace", "-version"], env=self.env, capture_output=True,
                                      text=True).stdout.strip() or f"pyradiance {pyradiance.__version__}"

    def irradiance(self, scene, points, options):
        """(lux per point, seconds for oconv + rtrace, the rtrace command)."""
        with tempfile.TemporaryDirectory() as tmp:
            octree = pathlib.Path(tmp) / "scene.oct"
            t = time.perf_counter()
            with open(octree, "wb") as f:
                subprocess.run(["oconv", "-f", scene.name], cwd=scene.parent, env=self.env, stdout=f, check=True)
            rays = "".join(" ".join(map(str, p)) + "\n" for p in points)
            cmd = ["rtrace", "-h", "-I", "-ov", *options, str(octree)]
            out = subprocess.run(cmd, input=rays, capture_output=True, text=True, env=self.env, check=True)
            seconds = time.perf_counter() - t
        rgb = [[float(v) for v in line.split()] for line in out.stdout.splitlines() if line.strip()]
        lux = [RADIANCE_EFFICACY * (0.2651058 * r + 0.6701058 * g + 0.0647884 * b) for r, g, b in rgb]
        return lux, seconds, "rtrace -h -I -ov " + " ".join(options)


RADIANCE_DIRECT = ["-ab", "0", "-dj", "0", "-ds", "0.01", "-dt", "0", "-dc", "1", "-lw", "1e-6"]


# Radiance under a sky (glow sources are seen by the ambient calculation only): one ambient
# bounce (the room is black), no ambient cache (-aa 0: each point its own hemisphere), 4096
# divisions with 1024 super-samples, the settings of scene-formats.md's sky check.
RADIANCE_SKY = ["-ab", "1", "-ad", "4096", "-as", "1024", "-aa", "0", "-lw", "1e-5"]


RADIANCE_BOX_REPEATS = 2000  # rtrace runs per floor point in the box


def radiance_box_options(rho):
    """Radiance as a path tracer: -aa 0 -ad 1 (one ambient ray per bounce, no cache), enough
    ambient bounces that the truncated ρ^(ab+1) is below 10⁻⁴, Russian roulette past -lw."""
    ab = 0 if rho == 0 else math.ceil(math.log(1e-4) / math.log(rho)) - 1
    return ["-ab", str(ab), "-ad", "1", "-as", "0", "-aa", "0", "-lr", "0", "-lw", "1e-7",
            "-dj", "0", "-ds", "0.01", "-dt", "0", "-dc", "1"]
