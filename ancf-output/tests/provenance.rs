//! The build script's provenance outside a git checkout (a source tarball):
//! the script, compiled on its own and run in an empty folder, records the
//! commit as "unknown", not dirty, and the compiler's version.

use std::process::Command;

#[test]
fn without_git_the_commit_is_unknown() {
    let dir = std::env::temp_dir().join(format!("ancf-provenance-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    let exe = dir.join("provenance");
    let built = Command::new(&rustc)
        .args(["--edition", "2024", "-o"])
        .arg(&exe)
        .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/build.rs"))
        // The folder the script takes for the package's: no .git above it
        // (the temporary directory is outside any checkout).
        .env("CARGO_MANIFEST_DIR", &dir)
        .output()
        .expect("rustc runs");
    assert!(
        built.status.success(),
        "{}",
        String::from_utf8_lossy(&built.stderr)
    );
    let out = Command::new(&exe)
        .current_dir(&dir)
        .env("RUSTC", &rustc)
        .output()
        .expect("the script runs");
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("cargo:rustc-env=ANCF_GIT_COMMIT=unknown\n"),
        "{text}"
    );
    assert!(
        text.contains("cargo:rustc-env=ANCF_GIT_DIRTY=false\n"),
        "{text}"
    );
    assert!(
        text.contains("cargo:rustc-env=ANCF_RUSTC_VERSION=rustc "),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
