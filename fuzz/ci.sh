#!/usr/bin/env bash
# Fuzz every target for a short time (seconds per target, default 50), then rerun the corpus
# and the saved crashes. Exits non-zero when an input panics or aborts.
#
#   fuzz/ci.sh [SECONDS]          with coverage: its own instrumented release build (slow to build)
#   fuzz/ci.sh [SECONDS] --blind  without coverage: random mutations of the committed corpus,
#                                 on the ordinary debug build (debug assertions on), for CI
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-50}
if [ "${2:-}" = "--blind" ]; then
    cargo build -p stride-fuzz
    bin=${CARGO_TARGET_DIR:-target}/debug/stride-fuzz
else
    export RUSTC_WRAPPER=$PWD/fuzz/rustc-sancov.sh CARGO_TARGET_DIR=target/fuzz
    export CARGO_PROFILE_RELEASE_DEBUG_ASSERTIONS=true CARGO_PROFILE_RELEASE_DEBUG=0
    cargo build --release -p stride-fuzz
    bin=target/fuzz/release/stride-fuzz
fi
ref=../shared/reference
# Files in a target's crash folder (0 when it does not exist yet).
count_crashes() { if [ -d "fuzz/crashes/$1" ]; then ls "fuzz/crashes/$1" | wc -l; else echo 0; fi; }
models=crates/model/data/models
for t in osim storage study model_settings geometry; do
    seeds=()
    case $t in
    osim) [ -d $ref/models ] && seeds=(--seeds $ref/models) ;;
    storage) [ -d $ref/experimental ] && seeds=(--seeds $ref/experimental) ;;
    study) seeds=(--seeds studies) ;;
    model_settings) for f in $models/*/*.toml; do seeds+=(--seeds "$f"); done ;;
    geometry) for f in $models/*/*.geometry.json; do seeds+=(--seeds "$f"); done ;;
    esac
    before=$(count_crashes $t)
    $bin run $t --seconds "$seconds" --seed "$RANDOM" "${seeds[@]}"
    after=$(count_crashes $t)
    if [ "$after" -gt "$before" ]; then
        echo "fuzz target $t: new crashing inputs in fuzz/crashes/$t" >&2
        exit 1
    fi
done
