//! Tells the integration tests where the repository is: `REPOSITORY` is
//! the folder above this package's, where the scenes, docs and fixtures
//! the tests read live.

fn main() {
    let package = std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR");
    let repository = std::path::Path::new(&package)
        .parent()
        .expect("the tests package is a folder of the repository");
    println!("cargo:rustc-env=REPOSITORY={}", repository.display());
    println!("cargo:rerun-if-changed=build.rs");
}
