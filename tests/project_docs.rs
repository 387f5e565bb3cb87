//! What the project's own documents promise about their form: README
//! opens with the two commands a new user needs, and BENCHMARKS.md holds
//! the current state (at most 300 lines; history lives in git).

use std::path::Path;

fn read(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

#[test]
fn readme_opens_with_the_main_run_and_the_test_command() {
    let readme = read("README.md");
    let block: Vec<&str> = (readme.split("```").nth(1))
        .expect("README has a code block")
        .lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with("sh"))
        .collect();
    assert_eq!(block.len(), 2, "{block:?}");
    assert!(block[0].contains(" run scenes/"), "{}", block[0]);
    assert!(block[1].starts_with("bash scripts/test.sh"), "{}", block[1]);
    let first_block = readme.find("```").unwrap();
    assert!(
        readme[..first_block].lines().count() <= 3,
        "the commands come first"
    );
}

#[test]
fn benchmarks_hold_the_current_state_in_at_most_300_lines() {
    let text = read("BENCHMARKS.md");
    let lines = text.lines().count();
    assert!(lines <= 300, "BENCHMARKS.md has {lines} lines");
    // Every measured section names the CPU it was measured on.
    for section in text.split("\n## ").skip(1) {
        let title = section.lines().next().unwrap();
        if ["Method", "Tried and not adopted", "Hand-written"]
            .iter()
            .any(|t| title.starts_with(t))
        {
            continue;
        }
        assert!(
            section.contains("AMD EPYC") || section.contains("Intel Xeon"),
            "section \"{title}\" names no CPU"
        );
    }
}
