#!/usr/bin/env python3
"""Survey Mitsuba 3's own scene collection with Opticks (issue 12).

Runs `opticks trace FILE --paths N` on every `.xml` of the `scenes/`, `docs/scenes/` and
`tests/scenes/` folders of a checkout of Mitsuba's public `mitsuba-data` repository (from its
root, as Mitsuba's own tests do), and writes the report `docs/mitsuba-collection.md`: the files
that load, trace and render, and a table of what stops the others (the first error of each,
grouped by the element it names). The report is generated: it is never edited by hand, it is
re-made by running this script again (its header names the command, the date and the versions).

With `--compare`, each file that loads is also rendered by Opticks (light estimator, the file's
own camera) and by Mitsuba 3 (`mitsuba.load_file`, then `mitsuba.render` with Mitsuba's `path`
integrator at `max_depth` -1: the full solution Opticks computes, whatever integrator the file
names — a file's `direct` or depth-limited integrator computes something else, and Mitsuba's
`direct` with `bsdf_samples` 0 is not even that: `scenes/hello.xml` comes out 4× brighter with
it than with `path` or `ptracer`), and the table gives both images' mean RGB and their ratio,
with the file's own integrator for reference, and counts the files that agree. Mitsuba 3 must
be importable (`pip install mitsuba`; its LLVM variant needs `DRJIT_LIBLLVM_PATH`).

Usage:
    tools/mitsuba_collection.py --data PATH/TO/mitsuba-data [--opticks target/release/opticks]
        [--paths 4096] [--compare] [--compare-paths 1000000] [--spp 64] [--estimator bidirectional]
        [--camera-spp 4] [--timeout 300] [--out docs/mitsuba-collection.md | --out -]

Progress goes to stderr; the report to `--out` (default `docs/mitsuba-collection.md` of this
repository, replaced atomically at the end), or to stdout with `--out -`.

Nothing here is run by the test suite: the collection is not part of this repository.
"""

import argparse
import datetime
import os
import re
import subprocess
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

FOLDERS = ["scenes", "docs/scenes", "tests/scenes"]
REPO = Path(__file__).resolve().parent.parent
DEFAULT_OUT = REPO / "docs" / "mitsuba-collection.md"
# Within these relative differences in every channel a file counts as agreeing with Mitsuba.
AGREEMENT = [0.01, 0.0015]


def git_version(folder: Path) -> str:
    """The short commit of a git checkout (with `-dirty` if it has changes), else a note."""
    try:
        run = subprocess.run(["git", "-C", str(folder), "describe", "--always", "--dirty"],
                             capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.TimeoutExpired):
        return "(git not available)"
    return run.stdout.strip() if run.returncode == 0 else "(not a git checkout)"


def command_line(argv) -> str:
    """This run's command, with the machine-specific paths (`--data`, `--opticks`) as words."""
    words, i = ["tools/mitsuba_collection.py"], 0
    while i < len(argv):
        a = argv[i]
        for flag, word in (("--data", "DIR"), ("--opticks", "OPTICKS")):
            if a == flag and i + 1 < len(argv):
                words += [flag, word]
                i += 1
                break
            if a.startswith(flag + "="):
                words.append(f"{flag}={word}")
                break
        else:
            words.append(a)
        i += 1
    return " ".join(words)


def fmt(values) -> str:
    """Numbers as the tables print them: four significant digits."""
    return ", ".join(f"{x:.4g}" for x in values)


def agrees(ours, theirs, tol: float) -> bool:
    """Every channel's ratio, as printed (four significant digits), within tol of 1; a channel
    black in both images agrees (its ratio is printed as nan)."""
    for a, b in zip(ours, theirs):
        if b > 0:
            if abs(float(f"{a / b:.4g}") - 1) > tol:
                return False
        elif float(f"{a:.4g}") != 0:
            return False
    return True


def first_error(stderr: str) -> str:
    for line in stderr.splitlines():
        if line.startswith("error:"):
            return line[len("error:"):].strip()
    lines = [l for l in stderr.splitlines() if l.strip()]
    return lines[-1] if lines else "(no message)"


def classify(rel: str, error: str) -> str:
    """The row of the 'what stops the others' table an error belongs to."""
    fragment = "/include/" in f"/{rel}" or "/fragments/" in f"/{rel}"
    if "scene has no triangles" in error:
        return "a fragment without geometry (meant to be included): \"the scene has no triangles\""
    if fragment and "cannot read mesh file" in error:
        return "a fragment loaded on its own: its mesh files are relative to the including scene"
    if fragment and "included file" in error and "not found" in error:
        return "a fragment loaded on its own: its includes are relative to the including scene"
    if fragment and re.search(r"no (object|element) with id|undefined id|refers to", error):
        return "a fragment loaded on its own: refers to ids of the including scene"
    m = re.search(r'<(\w+) type="([\w.]+)"[^>]*>: unsupported', error)
    if m:
        elem, kind = m.groups()
        if elem == "texture":
            return "`<texture type=…>` (textures)"
        return f'`<{elem} type="{kind}">`'
    m = re.search(r"unsupported element <(\w+)>", error)
    if m:
        return "`<texture type=…>` (textures)" if m.group(1) == "texture" else f"`<{m.group(1)}>`"
    if "medium" in error and "scatter" in error:
        return "a scattering `<medium>` (only absorbing interiors)"
    return f"`{error[:80]}`"


def trace(opticks: str, data: Path, rel: str, paths: int, out: Path, timeout: int):
    try:
        run = subprocess.run(
            [opticks, "trace", rel, "--paths", str(paths), "-o", str(out), "--overwrite", "--quiet"],
            cwd=data, capture_output=True, text=True, timeout=timeout,
        )
    except subprocess.TimeoutExpired:
        return False, f"(no answer within {timeout} s)"
    return run.returncode == 0, first_error(run.stderr)


def integrator_of(path: Path) -> str:
    text = path.read_text(errors="replace")
    m = re.search(r'<integrator\s+type=["\']([^"\']+)["\']', text)
    depth = re.search(r'name=["\']max_depth["\']\s+value=["\']([^"\']+)["\']', text)
    kind = m.group(1) if m else "(none in the file)"
    return f"{kind}, max_depth {depth.group(1) if depth else '-1'}"


def mean_rgb(image):
    """Mean of the first three channels (a Mitsuba film may carry AOVs after them)."""
    import numpy as np
    a = np.array(image)
    return a[:, :, :3].reshape(-1, 3).mean(axis=0)


def compare(args, data: Path, rel: str, tmp: Path):
    import mitsuba as mi
    dataset, ours = tmp / "c.opds", tmp / "ours.exr"
    ok, err = trace(args.opticks, data, rel, args.compare_paths, dataset, args.timeout)
    if not ok:
        return None, f"trace: {err}"
    estimator = ["--estimator", args.estimator]
    if args.estimator == "bidirectional":
        estimator += ["--spp", str(args.camera_spp)]
    run = subprocess.run([args.opticks, "render", str(dataset), "-o", str(ours), "--quiet", *estimator],
                         cwd=data, capture_output=True, text=True, timeout=args.timeout)
    if run.returncode != 0:
        return None, f"render: {first_error(run.stderr)}"
    cwd = os.getcwd()
    try:
        os.chdir(data / Path(rel).parent)
        scene = mi.load_file(Path(rel).name)
        path = mi.load_dict({"type": "path", "max_depth": -1})
        theirs = mean_rgb(mi.render(scene, integrator=path, spp=args.spp))
    except Exception as e:  # a scene Mitsuba itself cannot render: say so
        return None, f"Mitsuba: {str(e).splitlines()[0][:100]}"
    finally:
        os.chdir(cwd)
    return (mean_rgb(mi.Bitmap(str(ours))), theirs), ""


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--data", required=True, type=Path, help="root of a mitsuba-data checkout")
    p.add_argument("--opticks", default=str(REPO / "target/release/opticks"))
    p.add_argument("--paths", type=int, default=4096)
    p.add_argument("--timeout", type=int, default=300)
    p.add_argument("--compare", action="store_true")
    p.add_argument("--compare-paths", type=int, default=1_000_000)
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--estimator", default="bidirectional", choices=["bidirectional", "light"],
                   help="Opticks's estimator for --compare (the light estimator cannot see an environment directly)")
    p.add_argument("--camera-spp", type=int, default=4, help="camera paths per pixel of the bidirectional render")
    p.add_argument("--variant", default="llvm_ad_rgb")
    p.add_argument("--out", default=str(DEFAULT_OUT),
                   help="the report's file (default docs/mitsuba-collection.md of this repository; - for stdout)")
    args = p.parse_args()
    if args.out != "-" and not Path(args.out).resolve().parent.is_dir():
        sys.exit(f"--out {args.out}: its folder does not exist")  # before hours of rendering
    args.opticks = str(Path(args.opticks).resolve())
    data = args.data.resolve()
    files = sorted(str(f.relative_to(data)) for d in FOLDERS for f in (data / d).rglob("*.xml"))
    if not files:
        sys.exit(f"no .xml files under {', '.join(FOLDERS)} of {data}")
    loaded, stopped = [], defaultdict(list)
    out = []  # the report's lines
    with tempfile.TemporaryDirectory() as t:
        tmp = Path(t)
        for rel in files:
            ok, err = trace(args.opticks, data, rel, args.paths, tmp / "s.opds", args.timeout)
            if ok:
                loaded.append(rel)
            else:
                stopped[classify(rel, err)].append(rel)
            print(f"{'ok ' if ok else '-- '} {rel}" + ("" if ok else f": {err[:120]}"), file=sys.stderr)
        mitsuba = None
        if args.compare:
            import mitsuba as mi
            mi.set_variant(args.variant)
            mitsuba = getattr(mi, "__version__", None) or getattr(mi, "MI_VERSION", "3")
        out += header(args, data, len(files), mitsuba)
        out.append(f"**{len(loaded)} of {len(files)} files load, trace and render** (`opticks trace FILE`): "
                   + ", ".join(f"`{f}`" for f in loaded) + ".\n")
        out.append("| what stops the others (the first error each file gives) | files |\n|---|---|")
        for why, fs in sorted(stopped.items(), key=lambda kv: (-len(kv[1]), kv[0])):
            out.append(f"| {why} | {len(fs)}: " + ", ".join(f"`{f}`" for f in fs) + " |")
        if args.compare:
            rows, measured = [], []
            for rel in loaded:
                means, note = compare(args, data, rel, tmp)
                integ = integrator_of(data / rel)
                if means is None:
                    rows.append(f"| `{rel}` | {integ} | — | — | {note} |")
                    continue
                o, m = means
                measured.append((o, m))
                ratio = [a / b if b > 0 else float("nan") for a, b in zip(o, m)]
                rows.append(f"| `{rel}` | {integ} | {fmt(o)} | {fmt(m)} | {fmt(ratio)} |")
                print(f"   {rel}: {fmt(ratio)}", file=sys.stderr)
            how = f"{args.estimator} estimator, {args.compare_paths} light paths"
            if args.estimator == "bidirectional":
                how += f", {args.camera_spp} camera paths per pixel"
            counts = [sum(agrees(o, m, tol) for o, m in measured) for tol in AGREEMENT]
            out.append(f"\n## Against Mitsuba 3\n\n"
                       f"Opticks ({how}) against Mitsuba {mitsuba} (`{args.variant}`, `path` with max_depth -1, "
                       f"{args.spp} spp), image mean RGB. Both sides are noisy at these counts (Mitsuba's "
                       f"most on the small `tests/scenes` images), so a ratio within about 1% is agreement. "
                       f"Of the {len(measured)} files Mitsuba renders, **{counts[0]} agree within "
                       f"{AGREEMENT[0]:.0%} in every channel, {counts[1]} within {AGREEMENT[1]:.2%}** "
                       f"(counted from the ratios as printed; a channel black in both images agrees). "
                       f"Files Mitsuba itself cannot load say so in the ratio column.\n")
            out.append("| file | the file's own integrator | Opticks | Mitsuba `path` | ratio |\n|---|---|---|---|---|")
            out += rows
    write_report("\n".join(out) + "\n", args.out)


def header(args, data: Path, n_files: int, mitsuba) -> list:
    """The generated report's title and provenance: which command made it, when, from what."""
    # Opticks's version is that of the checkout this script is in (whose binary it runs by default).
    made = [f"Opticks {git_version(REPO)}", f"`mitsuba-data` {git_version(data)}"]
    if mitsuba:
        made.append(f"Mitsuba {mitsuba} (`{args.variant}`)")
    return [
        "<!-- Generated by tools/mitsuba_collection.py: do not edit by hand; run it again. -->",
        "# Mitsuba's own scene collection, surveyed\n",
        f"Generated by `{command_line(sys.argv[1:])}` on {datetime.date.today().isoformat()} "
        f"({', '.join(made)}). Do not edit this file: run the command again (`DIR` is a checkout of "
        "Mitsuba's public `mitsuba-data` repository). The reference of what Opticks reads is "
        "[`scene-formats.md`](scene-formats.md#mitsuba-3-xml); what these numbers mean, "
        "[`validation.md`](validation.md#mitsubas-own-scene-collection).\n",
        f"Every `.xml` file of the {', '.join(f'`{d}/`' for d in FOLDERS)} folders of `mitsuba-data` "
        f"({n_files} files; fragments meant to be included count as files too), loaded with "
        f"`opticks trace FILE --paths {args.paths}` from the repository's root. Their data is not "
        "part of this repository.\n",
        "## Which files load\n",
    ]


def write_report(text: str, out: str):
    """The report to stdout (`-`), or into its file atomically (a temporary file, renamed)."""
    if out == "-":
        sys.stdout.write(text)
        return
    path = Path(out)
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    tmp.write_text(text)
    os.replace(tmp, path)
    print(f"wrote {path}", file=sys.stderr)


if __name__ == "__main__":
    main()
