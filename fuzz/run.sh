#!/usr/bin/env bash
# Runs the fuzz targets, each for SECONDS seconds (default 15), from seeds taken from testdata/,
# scenes/ and fuzz/seeds/ (copied into fuzz/corpus/, which keeps what the fuzzer finds between
# runs and is not committed). Needs only the nightly toolchain (`rustup toolchain install
# nightly`): the targets are built here with the coverage instrumentation libFuzzer needs, the
# flags cargo-fuzz passes, so cargo-fuzz itself is not needed (`cargo fuzz run TARGET` works as
# well, for a sanitizer or a longer campaign).
#
# No sanitizer by default: the readers are safe Rust, and without AddressSanitizer the targets
# build about twice as fast and run several times as many executions in the same seconds, which
# is what a short CI run needs. OPTICKS_FUZZ_SANITIZER=address adds it.
#
# OPTICKS_FUZZ_SEED fixes libFuzzer's seed (0, the default: a new one each run; `.ci/run` uses
# 1, so CI explores the same inputs every time and a red run is a find, not chance).
#
# A crash stops the run with the input saved under fuzz/artifacts/TARGET/: fix the defect, then
# commit the input under testdata/fuzz-regressions/TARGET/ (a stable test replays every file
# there).
#
#   fuzz/run.sh            # every target, 15 s each
#   fuzz/run.sh 600 vrml   # one target, ten minutes
set -euo pipefail
cd "$(dirname "$0")"
seconds=${1:-15}
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
    targets=(mitsuba vrml obj_mtl gltf ies camera_path dataset ply serialized texture spectrum
        meter_points cluster_wire mitsuba_include radiance)
fi

# seed TARGET FILE...: small files only (libFuzzer mutates better, and faster, from small inputs).
seed() {
    local target=$1
    shift
    mkdir -p "corpus/$target"
    for f in "$@"; do
        if [ -f "$f" ] && [ "$(stat -c %s "$f")" -le 65536 ]; then
            cp "$f" "corpus/$target/seed-$(echo "$f" | tr '/' '_')"
        fi
    done
}
seed mitsuba $(find ../testdata ../scenes -name '*.xml')
seed vrml $(find ../testdata ../scenes -name '*.wrl')
seed obj_mtl seeds/obj_mtl/* $(find ../testdata -name '*.obj')
seed gltf seeds/gltf/* ../testdata/gltf/cornell.gltf
seed ies $(find ../testdata ../scenes -name '*.ies')
seed camera_path seeds/camera_path/*
seed dataset seeds/dataset/*
seed ply $(find ../testdata ../scenes -name '*.ply')
seed serialized $(find ../testdata ../scenes -name '*.serialized')
seed texture seeds/texture/* $(find ../testdata ../scenes -name '*.png' -o -name '*.jpg' -o -name '*.hdr' -o -name '*.exr')
seed spectrum seeds/spectrum/*
seed meter_points seeds/meter_points/*
seed cluster_wire seeds/cluster_wire/*
seed mitsuba_include seeds/mitsuba_include/* $(find ../testdata ../scenes -name '*.xml')
seed radiance seeds/radiance/* $(find ../testdata -name '*.rad')

# The instrumentation of `cargo fuzz build -O`: coverage counters and comparison tracing for
# libFuzzer, debug assertions and overflow checks on. An explicit --target keeps build scripts
# and proc-macros uninstrumented.
triple=$(rustc +nightly -vV | sed -n 's/^host: //p')
flags="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4"
flags+=" -Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table"
flags+=" -Cllvm-args=-sanitizer-coverage-trace-compares --cfg fuzzing -Cdebug-assertions -Coverflow-checks"
if [ "${OPTICKS_FUZZ_SANITIZER:-none}" = address ]; then
    flags+=" -Zsanitizer=address"
fi
echo "== building the fuzz targets (nightly, $triple)"
bins=()
for t in "${targets[@]}"; do bins+=(--bin "$t"); done
# The binaries go to fuzz/target whatever CARGO_TARGET_DIR says (the loop below runs them from
# there; a binary that is missing is an error, never a silent pass).
RUSTFLAGS="$flags" cargo +nightly build --release --target-dir target --target "$triple" "${bins[@]}"

for t in "${targets[@]}"; do
    echo "== fuzzing $t for ${seconds} s"
    if [ ! -x "target/$triple/release/$t" ]; then
        echo "fuzz target $t was not built: target/$triple/release/$t is missing" >&2
        exit 1
    fi
    mkdir -p "artifacts/$t"
    # -rss_limit_mb: a reader must never need more for a small input; -timeout: nor hang.
    "target/$triple/release/$t" "corpus/$t" -artifact_prefix="artifacts/$t/" \
        -max_total_time="$seconds" -seed="${OPTICKS_FUZZ_SEED:-0}" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 2>&1 |
        grep -E '^(==|stat::number_of_executed_units|Done|SUMMARY|ERROR|.*(panicked|deadly signal|Test unit written))' || true
    # grep swallowed the exit status: a crash leaves an artifact, which is what fails the run.
    if compgen -G "artifacts/$t/*" >/dev/null; then
        echo "fuzz target $t found a crashing input: fuzz/artifacts/$t/" >&2
        ls "artifacts/$t" >&2
        exit 1
    fi
done
