//! What a structure with one mode feels from a support's force
//! (`output.response_frequencies`): summary.json's `supports[i].response`,
//! each component's oscillator at each frequency, checked against the
//! force history the run recorded; and the keys' errors.

use ancf::run::run_in_memory;
use ancf_core::scene::Scene;

/// scenes/pendulum.toml (a pinned wire swinging down from the horizontal,
/// about 1 Hz) to 0.5 s, with `output` appended to its `[output]` table.
fn pendulum(output: &str) -> String {
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/pendulum.toml"))
            .unwrap()
            .replace("end_time = 1.0", "end_time = 0.5");
    assert!(text.contains("end_time = 0.5"));
    match text.contains("[output]") {
        true => text.replace("[output]", &format!("[output]\n{output}")),
        false => format!("{text}\n[output]\n{output}\n"),
    }
}

/// A stiff oscillator (far above the swing) follows the force: its peak is
/// the largest |F| of each component; a soft one (far below) hardly leaves
/// the force it starts from. Between them, every peak lies within those
/// bounds' reach, and the damping is the one asked for.
#[test]
fn a_supports_response_follows_its_force_above_and_ignores_it_below() {
    let scene = Scene::from_toml(&pendulum(
        "response_frequencies = [0.01, 3.0, 400.0]\nresponse_damping = 0.05",
    ))
    .unwrap();
    let run = run_in_memory(&scene);
    assert_eq!(run.summary.status, ancf::output::RunStatus::Completed);
    let history = &run.support_loads[0];
    let response = &run.summary.supports[0].response;
    assert_eq!(response.len(), 3);
    for (r, f) in response.iter().zip([0.01, 3.0, 400.0]) {
        assert_eq!((r.frequency, r.damping), (f, 0.05));
    }
    // The force at t = 0, then one per step.
    let start = run.summary.supports[0].static_force;
    for c in 0..3 {
        let series: Vec<f64> = std::iter::once(start[c])
            .chain(history.force.iter().map(|f| f[c]))
            .collect();
        let largest = series.iter().fold(0.0f64, |m, f| m.max(f.abs()));
        let first = series[0].abs();
        assert!(largest > 0.0 || c == 1, "component {c} carries load");
        // 400 Hz (below the steps' Nyquist 500 Hz): quasi-static, its dynamic
        // overshoot well below 1 %.
        let stiff = response[2].peak[c];
        assert!(
            (stiff - largest).abs() <= 1e-2 * largest,
            "component {c}: {stiff} against the largest |F| {largest}"
        );
        // 0.01 Hz over 0.5 s: ω t = 0.03, the oscillator moves by (ω t)²/2.
        let soft = response[0].peak[c];
        assert!(
            (soft - first).abs() <= 1e-3 * largest.max(1.0),
            "component {c}: {soft} against the first |F| {first}"
        );
        // Near the swing: between the start and twice the largest change.
        let mid = response[1].peak[c];
        assert!(
            mid >= first && mid <= first + 2.0 * (largest + first),
            "{mid}"
        );
    }
    // Not asked for: not computed, not written.
    let plain = run_in_memory(&Scene::from_toml(&pendulum("")).unwrap());
    assert!(plain.summary.supports[0].response.is_empty());
    let json = serde_json::to_value(&plain.summary).unwrap();
    assert!(json["supports"][0].get("response").is_none());
}

#[test]
fn response_keys_are_checked_and_named() {
    let field = |output: &str| Scene::from_toml(&pendulum(output)).unwrap_err().field;
    assert_eq!(
        field("response_frequencies = [5.0, 0.0]"),
        "output.response_frequencies[1]"
    );
    assert_eq!(
        field("response_frequencies = [5.0]\nresponse_damping = 1.5"),
        "output.response_damping"
    );
    assert_eq!(field("response_damping = 0.05"), "output.response_damping");
}
