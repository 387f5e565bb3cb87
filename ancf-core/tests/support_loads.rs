//! The force each support exerts on the wire, step by step: after a span
//! breaks, the remaining support's history is the tower's broken-wire load.
//!
//! A taut wire without gravity, pretensioned between two pins and released
//! at one end: the far support keeps its static reaction until the
//! unloading wave arrives at t = L / c, c = √(E / ρ), and then loses it
//! (for a bar that carries compression, to about the opposite value). A
//! stiff bar swinging from a pin loads it as a rigid body does.

use ancf_core::math::vec3::norm;
use ancf_core::prelude::*;

#[test]
fn the_far_support_holds_until_the_axial_wave_arrives() {
    let (l, elements, e, rho, r) = (10.0_f64, 100, 2e11_f64, 7800.0_f64, 0.005_f64);
    let strain = 1e-4;
    let steel = Material::st_venant_kirchhoff(rho, e, 0.0, 1.0);
    let end = |node: usize, x: f64, release: Option<f64>| Support {
        node,
        kind: SupportKind::Pin,
        position: Some([x, 0.0, 0.0]),
        release_time: release,
    };
    let model = WireBuilder::new(l, elements)
        .layer(steel, r)
        // Node 0 lets go at once; the far end holds.
        .support_with(end(0, 0.0, Some(1e-9)))
        .support_with(end(elements, l * (1.0 + strain), None))
        .build()
        .unwrap();
    let c = (e / rho).sqrt();
    let arrival = l / c;
    let settings = DynamicSettings {
        time_step: 1e-5,
        end_time: 1.6 * arrival,
        spectral_radius: 0.8,
        ..Default::default()
    };
    let mut sim = Simulation::new(&model, settings, Initial::Static { load_steps: 1 }).unwrap();
    while !sim.is_finished() {
        sim.step().unwrap();
    }
    let tension = e * std::f64::consts::PI * r * r * strain;
    let far = &sim.support_loads()[1];
    // The far pin holds the stretched wire out: +x.
    let fx: Vec<(f64, f64)> = far
        .time
        .iter()
        .zip(&far.force)
        .map(|(t, f)| (*t, f[0]))
        .collect();
    // Before the wave: the static tension, to 2 %.
    for &(t, f) in fx.iter().filter(|(t, _)| *t < 0.9 * arrival) {
        assert!(
            (f / tension - 1.0).abs() < 0.02,
            "t = {t:.3e} s: {f:.2} N against {tension:.2} N"
        );
    }
    // After it the reaction has fallen: the unloading wave reflects at the
    // fixed end with its own sign, so the pin sees the tension's change
    // twice — a bar's end goes from +T to about −T.
    let late: Vec<f64> = fx
        .iter()
        .filter(|(t, _)| *t > 1.2 * arrival)
        .map(|x| x.1)
        .collect();
    assert!(!late.is_empty());
    for &f in &late {
        assert!(
            f < 0.2 * tension,
            "{f:.2} N after the wave against {tension:.2} N"
        );
    }
    let mean = late.iter().sum::<f64>() / late.len() as f64;
    assert!(
        (mean / tension + 1.0).abs() < 0.2,
        "mean {mean:.2} N after the wave, −{tension:.2} N expected"
    );
    // The released support carries nothing once it has let go.
    let near = &sim.support_loads()[0];
    assert!(near.force.iter().skip(1).all(|f| *f == [0.0; 3]));
}

/// From a static equilibrium, the supports' forces at t = 0 are the static
/// reactions, and a step later (nothing moves) the integrator's own balance
/// M a + Q − Q_ext on the held coordinates gives them again and carries the
/// wire's weight.
#[test]
fn the_supports_hold_the_static_reactions_while_nothing_moves() {
    let (l, elements) = (20.0_f64, 20);
    let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
    let model = WireBuilder::new(l, elements)
        .layer(steel, 0.005)
        .support(0, SupportKind::Pin)
        .support(elements, SupportKind::Pin)
        .gravity([0.0, 0.0, -9.81])
        .build()
        .unwrap();
    // The same static solve as the simulation's initial one.
    let st = StaticSettings {
        load_steps: 1,
        ..Default::default()
    };
    let statics = solve_static(&model, &st).unwrap();
    let settings = DynamicSettings {
        time_step: 1e-3,
        end_time: 2e-3,
        ..Default::default()
    };
    let mut sim = Simulation::new(&model, settings, Initial::Static { load_steps: 1 }).unwrap();
    let initial = sim.initial_support_forces().to_vec();
    let expected: Vec<[f64; 3]> = statics.reactions.iter().map(|(_, f)| *f).collect();
    assert_eq!(initial, expected);
    sim.step().unwrap();
    // The static solve leaves a residual of 1e-10 of the load; on the
    // gradient coordinates of least inertia it becomes an acceleration of
    // a few m/s², whose mass coupling moves a reaction by parts in 1e9 of
    // itself; a step of motion from there, by parts in 1e7.
    for (i, (r_static, h)) in expected.iter().zip(sim.support_loads()).enumerate() {
        let r = h.force[0];
        let scale = norm(*r_static);
        for k in 0..3 {
            assert!(
                (r_static[k] - r[k]).abs() <= 1e-6 * scale,
                "support {i}, component {k}: {} N after a step against {} N static",
                r[k],
                r_static[k]
            );
        }
    }
    let weight = model.total_mass() * 9.81;
    let held: f64 = sim.support_loads().iter().map(|h| h.force[0][2]).sum();
    assert!(
        (held / weight - 1.0).abs() < 1e-6,
        "{held} N held after a step against a weight of {weight} N"
    );
}

/// A stiff bar let go level from a pin swings as a rigid body: it passes
/// under the pin at t = √(L / 3g) ∫₀^{π/2} sin^{-1/2}θ dθ, and there the pin
/// carries its weight and the centripetal force of its centre, m (g +
/// ω² L / 2) with ω² = 3g / L: 2.5 m g (and nothing sideways: the angular
/// acceleration is zero there).
#[test]
fn a_stiff_bar_swinging_from_a_pin_loads_it_as_a_rigid_body() {
    let (l, elements, g) = (1.0_f64, 8, 9.81_f64);
    let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.0, 1.0);
    let model = WireBuilder::new(l, elements)
        .layer(steel, 0.02)
        .support(0, SupportKind::Pin)
        .gravity([0.0, 0.0, -g])
        .build()
        .unwrap();
    let settings = DynamicSettings {
        time_step: 1e-4,
        end_time: 0.55,
        spectral_radius: 0.8,
        ..Default::default()
    };
    let mut sim = Simulation::new(&model, settings, Initial::Reference).unwrap();
    // (time, tip x) per step, to find when the bar hangs under the pin.
    let mut tip_x = Vec::new();
    while !sim.is_finished() {
        sim.step().unwrap();
        let state = sim.state();
        tip_x.push((state.time, model.node_position(&state.q, elements)[0]));
    }
    let k = tip_x
        .windows(2)
        .position(|w| w[0].1 > 0.0 && w[1].1 <= 0.0)
        .expect("the bar passes under the pin");
    let ((t0, x0), (t1, x1)) = (tip_x[k], tip_x[k + 1]);
    let crossing = t0 + (t1 - t0) * x0 / (x0 - x1);
    // Γ(1/4) Γ(1/2) / (2 Γ(3/4)).
    let integral = 2.622_057_554_292_119_8;
    let expected = (l / (3.0 * g)).sqrt() * integral;
    assert!(
        (crossing / expected - 1.0).abs() < 2e-3,
        "under the pin at {crossing:.5} s, a rigid bar at {expected:.5} s"
    );
    // The pin's force there (support histories are at the steps' midpoints),
    // averaged over ± 5 ms: the bar rings in its first bending mode (about
    // 125 Hz, set off by the release) and that shakes the pin sideways by
    // ± 10 % of the weight.
    let weight = model.total_mass() * g;
    let pin = &sim.support_loads()[0];
    let near: Vec<[f64; 3]> = pin
        .time
        .iter()
        .zip(&pin.force)
        .filter(|(t, _)| (**t - crossing).abs() <= 5e-3)
        .map(|(_, f)| *f)
        .collect();
    let mean = |k: usize| near.iter().map(|f| f[k]).sum::<f64>() / near.len() as f64;
    let (fx, fz) = (mean(0), mean(2));
    assert!(
        (fz / (2.5 * weight) - 1.0).abs() < 1e-2,
        "the pin's vertical force {fz:.2} N under the pin, 2.5 m g = {:.2} N",
        2.5 * weight
    );
    assert!(
        fx.abs() < 0.02 * weight,
        "the pin's sideways force {fx:.2} N under the pin, weight {weight:.2} N"
    );
    // And that is the largest force of the swing, filtered as reported.
    let load = pin.summary(&pin.filtered(60.0));
    assert!(
        (load.filtered_peak_force / (2.5 * weight) - 1.0).abs() < 5e-3,
        "filtered peak {:.2} N against 2.5 m g = {:.2} N",
        load.filtered_peak_force,
        2.5 * weight
    );
}
