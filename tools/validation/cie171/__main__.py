"""`python3 tools/validation/cie171 [options]`: the command line (see the package's docstring)."""
import argparse
import pathlib
import subprocess
import sys

if __package__ in (None, ""):  # run as a folder (python3 tools/validation/cie171): import it as the package
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
    __package__ = "cie171"

from . import box, daylight, direct, pane  # noqa: E402 (after the path is set)
from .closed_forms import ROOT  # noqa: E402
from .opticks import Opticks  # noqa: E402
from .radiance import Radiance  # noqa: E402
from .report import Run, document  # noqa: E402
from .scenes import write_scenes  # noqa: E402
from .tta_report import old_tta, splice_tta, time_to_accuracy  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=sys.modules[__package__].__doc__.split("\n\n")[0])
    ap.add_argument("--opticks", default=str(ROOT / "target/release/opticks"))
    ap.add_argument("--work", default=str(ROOT / "target/cie171"))
    ap.add_argument("--doc", default=str(ROOT / "docs/validation-cie171.md"))
    ap.add_argument("--no-radiance", action="store_true")
    ap.add_argument("--scenes-only", action="store_true")
    ap.add_argument("--time-to-accuracy", action="store_true",
                    help="also search each program's cheapest setting to each case's target (slow, ~20 min)")
    ap.add_argument("--time-to-accuracy-only", action="store_true",
                    help="run only that search and replace its section of the existing --doc")
    ap.add_argument("--time-to-accuracy-cases", default="",
                    help="only the cases whose title contains one of these comma-separated strings (trials)")
    args = ap.parse_args()

    write_scenes()
    if args.scenes_only:
        return
    work = pathlib.Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    opticks = Opticks(pathlib.Path(args.opticks).resolve(), work)
    version = subprocess.run([opticks.exe, "--version"], capture_output=True, text=True).stdout.strip()
    radiance = None
    if not args.no_radiance:
        try:
            radiance = Radiance()
        except ImportError:
            print("pyradiance not installed: Radiance not run", file=sys.stderr)

    if args.time_to_accuracy or args.time_to_accuracy_only:
        if radiance is None:
            sys.exit("--time-to-accuracy needs Radiance (pyradiance)")
    if args.time_to_accuracy_only:
        section = time_to_accuracy(opticks.exe, work, radiance, version, args.time_to_accuracy_cases)
        doc_path = pathlib.Path(args.doc)
        doc_path.write_text(splice_tta(doc_path.read_text(), section))
        print(f"wrote {args.doc}", file=sys.stderr)
        return
    # Without the flag the section of the previous run is kept (its own header says when it ran).
    tta_section = old_tta(args.doc)

    run = Run(opticks, radiance)
    direct.run_cases(run)
    box.run_cases(run)
    pane.run_case(run)
    daylight.run_cases(run)
    text = document(run, version)
    if args.time_to_accuracy:
        tta_section = time_to_accuracy(opticks.exe, work, radiance, version, args.time_to_accuracy_cases)
    pathlib.Path(args.doc).write_text(splice_tta(text, tta_section))
    print(f"wrote {args.doc}", file=sys.stderr)


if __name__ == "__main__":
    main()
