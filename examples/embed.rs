//! ancf-core embedded in a program: a two-layer conductor built
//! in code, falling onto a rod, run with `Simulation` — no scene file, no
//! output files. Prints time, tip position and the force on the rod every
//! millisecond, then when the wire first touched the rod.
//!
//! `cargo run --release --example embed`

use ancf_core::math::vec3::norm;
use ancf_core::prelude::*;
use std::ops::ControlFlow;

fn main() -> Result<(), Error> {
    // ACSR "Drake" as two smeared layers (scenes/wire_rod_impact.toml has the sources).
    let core = Material::st_venant_kirchhoff(5990.0, 154e9, 0.0, 0.1);
    let aluminium = Material::st_venant_kirchhoff(2026.0, 51.7e9, 0.0, 0.1);
    let model = WireBuilder::new(2.0, 32)
        .layer(core, 0.0052)
        .layer(aluminium, 0.01407)
        .support(0, SupportKind::Pin)
        .gravity([0.0, 0.0, -9.81])
        .rod(Rod::line([1.0, 0.0, -0.3], [0.0, 1.0, 0.0], 0.02, 5e7).with_friction(0.3))
        .build()?;
    let settings = DynamicSettings {
        time_step: 1e-4,
        end_time: 0.4,
        spectral_radius: 1.0,
        ..Default::default()
    };
    let mut sim = Simulation::new(&model, settings, Initial::Reference)?;
    println!("t (s),tip x (m),tip z (m),rod force (N)");
    // The observer sees the simulation after every step (10 steps = 1 ms).
    sim.run_until(0.4, |sim, info| {
        if sim.steps().0 % 10 == 0 {
            let tip = model.node_position(&sim.state().q, model.n_elements);
            let force = norm(info.rod_forces[0]);
            println!(
                "{:.3},{:.5},{:.5},{force:.1}",
                sim.state().time,
                tip[0],
                tip[2]
            );
        }
        ControlFlow::Continue(())
    })?;
    if let Some(t) = sim.contact().and_then(|c| c.first_time) {
        eprintln!("first contact at t = {t:.4} s");
    }
    Ok(())
}
