//! The Python package runs scenes through `ancf-output` and the core, not
//! through the command line: its dependency tree holds no clap, indicatif
//! or ctrlc (argument parsing, the terminal's progress bar, the Ctrl-C
//! handler are the program's).

use std::process::Command;

#[test]
fn the_python_package_depends_on_no_command_line_crate() {
    let manifest = concat!(env!("CARGO_MANIFEST_DIR"), "/ancf-python/Cargo.toml");
    let out = Command::new(env!("CARGO"))
        .args([
            "tree",
            "--locked",
            "-e",
            "normal",
            "--prefix",
            "none",
            "--manifest-path",
        ])
        .arg(manifest)
        .output()
        .expect("cargo runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "cargo tree failed: {stderr}");
    let tree = String::from_utf8(out.stdout).unwrap();
    let crates: Vec<&str> = tree.lines().filter_map(|l| l.split(' ').next()).collect();
    assert!(crates.contains(&"ancf-output") && crates.contains(&"ancf-core"));
    for cli in ["clap", "indicatif", "ctrlc", "ancf"] {
        assert!(
            !crates.contains(&cli),
            "ancf-python depends on {cli}:\n{tree}"
        );
    }
}
