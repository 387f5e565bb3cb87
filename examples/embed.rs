//! ancf-core embedded in a program (issue 15): a two-layer conductor built
//! in code, falling onto a rod, run with `Simulation` — no scene file, no
//! output files. Prints time, tip position and the force on the rod every
//! millisecond.
//!
//! `cargo run --release --example embed`

use ancf_core::forces::contact::Rod;
use ancf_core::material::Material;
use ancf_core::model::{SupportKind, WireBuilder};
use ancf_core::solve::dynamics::DynamicSettings;
use ancf_core::solve::simulation::{Initial, Simulation};

fn main() -> Result<(), Box<dyn std::error::Error>> {
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
    while !sim.is_finished() {
        sim.step()?;
        let (k, _) = sim.steps();
        if k % 10 == 0 {
            let tip = model.node_position(&sim.state().q, model.n_elements);
            let force = sim.rod_loads()[0]
                .force
                .last()
                .map_or(0.0, |f| ancf_core::math::vec3::norm(*f));
            println!(
                "{:.3},{:.5},{:.5},{force:.1}",
                sim.state().time,
                tip[0],
                tip[2]
            );
        }
    }
    Ok(())
}
