//! Build script of stride-solve: links the system IPOPT library when the `ipopt` feature is on
//! (found with pkg-config); does nothing otherwise.

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    #[cfg(feature = "ipopt")]
    link_ipopt();
}

/// Finds `ipopt` with pkg-config and links it, or stops the build with the fix.
///
/// Only `-lipopt` itself is linked (dynamically): `libipopt.so` records its own dependencies
/// (MUMPS, LAPACK, BLAS), whereas the extra `-l` flags of Debian's `ipopt.pc` name libraries
/// such as `-llapack` that have no development symlink unless their `-dev` packages are
/// installed.
#[cfg(feature = "ipopt")]
fn link_ipopt() {
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");
    let lib = pkg_config::Config::new()
        .atleast_version("3.11")
        .cargo_metadata(false)
        .probe("ipopt")
        .unwrap_or_else(|e| {
            panic!(
                "the `ipopt` feature of stride-solve needs the system IPOPT library (>= 3.11) \
                 visible to pkg-config.\n  On Debian/Ubuntu: apt-get install \
                 coinor-libipopt-dev pkg-config\n  pkg-config said: {e}"
            )
        });
    for dir in &lib.link_paths {
        println!("cargo:rustc-link-search=native={}", dir.display());
    }
    println!("cargo:rustc-link-lib=dylib=ipopt");
}
