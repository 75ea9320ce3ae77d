#!/usr/bin/env bash
# Fuzzes one mesh reader of the built package with atheris (coverage-guided, libFuzzer) for a
# bounded time: tests/fuzz/readers (docs/robustness.md). Atheris comes from the package index
# into a venv of its own (BUILD_DIR/fuzz_venv, Debian's NumPy seen through
# --system-site-packages), made once.
# Usage: run_fuzz_readers.sh SOURCE_DIR BUILD_DIR EXT SECONDS      (EXT: obj, off or ply)
# A finding stops the run with the input saved as BUILD_DIR/fuzz_readers/EXT/crash-* (or
# timeout-*: an input slower than 30 s; the timing tests hold the readers to 1 s, the margin
# is for a loaded machine). Fix the reader, then keep the input as
# tests/fuzz/readers/findings/EXT/<what it found>.EXT.
set -euo pipefail
source_dir=$1
build_dir=$2
ext=$3
seconds=${4:-120}
venv="$build_dir/fuzz_venv"
if ! "$venv/bin/python" -c "import atheris" 2> /dev/null; then
  rm -rf "$venv"
  /usr/bin/python3 -m venv --system-site-packages "$venv"
  "$venv/bin/python" -m pip install --no-cache-dir -q "atheris>=2.3,<4"
fi
work="$build_dir/fuzz_readers/$ext"
rm -rf "$work/seeds" "$work"/crash-* "$work"/timeout-* "$work"/oom-*
mkdir -p "$work/corpus"
readers="$source_dir/tests/fuzz/readers"
export PYTHONPATH="$build_dir/python:$readers:$source_dir/tests/python"
"$venv/bin/python" "$readers/seeds.py" ".$ext" "$work/seeds"
# New inputs go to the working corpus; the seeds and the kept findings are only read. A
# format without findings yet has no folder in git (libFuzzer stops on a missing corpus).
corpora=("$work/corpus" "$work/seeds")
[ -d "$readers/findings/$ext" ] && corpora+=("$readers/findings/$ext")
"$venv/bin/python" "$readers/fuzz_readers.py" ".$ext" "${corpora[@]}" \
  -max_total_time="$seconds" -timeout=30 -artifact_prefix="$work/" -print_final_stats=1
