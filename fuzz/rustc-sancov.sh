#!/bin/sh
# RUSTC_WRAPPER of the fuzz build: instruments the crates that read inputs with
# SanitizerCoverage edge guards (stable rustc options), leaves every other crate (and the
# harness, which implements the guard callbacks) as it is.
rustc="$1"
shift
case " $* " in
*" --crate-name stride_model "* | *" --crate-name stride_study "* | *" --crate-name roxmltree "* | \
    *" --crate-name stride_geometry "* | *" --crate-name serde_json "* | \
    *" --crate-name toml "* | *" --crate-name toml_edit "* | *" --crate-name winnow "* | \
    *" --crate-name toml_datetime "* | *" --crate-name serde_spanned "*)
    exec "$rustc" "$@" -Cpasses=sancov-module \
        -Cllvm-args=-sanitizer-coverage-level=3 \
        -Cllvm-args=-sanitizer-coverage-trace-pc-guard
    ;;
esac
exec "$rustc" "$@"
