#!/usr/bin/env bash
# Fuzz every target for a short time (seconds per target, default 50) with coverage, then
# rerun the corpus and the saved crashes. Exits non-zero when an input panics or aborts.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-50}
export RUSTC_WRAPPER=$PWD/fuzz/rustc-sancov.sh CARGO_TARGET_DIR=target/fuzz
export CARGO_PROFILE_RELEASE_DEBUG_ASSERTIONS=true CARGO_PROFILE_RELEASE_DEBUG=0
cargo build --release -p stride-fuzz
bin=target/fuzz/release/stride-fuzz
ref=../shared/reference
for t in osim storage study; do
    seeds=()
    case $t in
    osim) [ -d $ref/models ] && seeds=(--seeds $ref/models) ;;
    storage) [ -d $ref/experimental ] && seeds=(--seeds $ref/experimental) ;;
    study) seeds=(--seeds studies) ;;
    esac
    before=$(ls fuzz/crashes/$t 2>/dev/null | wc -l)
    $bin run $t --seconds "$seconds" --seed "$RANDOM" "${seeds[@]}"
    after=$(ls fuzz/crashes/$t 2>/dev/null | wc -l)
    if [ "$after" -gt "$before" ]; then
        echo "fuzz target $t: new crashing inputs in fuzz/crashes/$t" >&2
        exit 1
    fi
done
