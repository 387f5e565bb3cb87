//! Build script of `ancf-output`: build provenance. It records the git
//! commit the code is built from (and whether the work tree differed from
//! it) and the compiler's version as compile-time environment variables,
//! read by `build_info`: `ancf --version`, summary.json and the Python
//! package's `summary()` report them, so that a design number can be traced
//! to the code that computed it. Without git or a `.git` folder (a source
//! tarball) the commit is "unknown".

use std::path::Path;
use std::process::Command;

/// The output of `git args…` in `dir`, trimmed, when git succeeds.
fn git(dir: &Path, args: &[&str]) -> Option<String> {
    let out = Command::new("git")
        .arg("-C")
        .arg(dir)
        .args(args)
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn main() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    // The package's own version, not the one of whoever depends on it.
    let commit = git(root, &["rev-parse", "HEAD"]).unwrap_or_else(|| "unknown".into());
    // Tracked files that differ from the commit (untracked files do not
    // change what is built).
    let dirty = commit != "unknown"
        && git(root, &["status", "--porcelain", "--untracked-files=no"])
            .is_some_and(|s| !s.is_empty());
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let rustc_version = Command::new(rustc)
        .arg("--version")
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_else(|| "unknown".into());
    println!("cargo:rustc-env=ANCF_GIT_COMMIT={commit}");
    println!("cargo:rustc-env=ANCF_GIT_DIRTY={dirty}");
    println!("cargo:rustc-env=ANCF_RUSTC_VERSION={rustc_version}");
    // Again when the commit moves or a source changes (the dirty flag);
    // not on every `git status`, which touches the index.
    for path in [
        "../.git/HEAD",
        "../.git/refs",
        "../.git/packed-refs",
        "../src",
        "src",
        "build.rs",
        "../ancf-core/src",
        "../ancf-core/build.rs",
        "../ancf-macros/src",
        "../ancf-python/src",
        "../Cargo.toml",
        "../Cargo.lock",
    ] {
        println!("cargo:rerun-if-changed={path}");
    }
}
