//! A snapshot (a checkpoint's state) that does not fit its model is
//! refused when resuming, naming the field — never a panic, a stack
//! overflow or a run that claims completion at half its end time.

use ancf_core::prelude::*;
use ancf_core::solve::simulation::Snapshot;

fn model() -> Model {
    let steel = Material::st_venant_kirchhoff(7800.0, 2e11, 0.3, 1.0);
    WireBuilder::new(1.0, 4)
        .layer(steel, 0.01)
        .support(0, SupportKind::Pin)
        .gravity([0.0, 0.0, -9.81])
        .rod(Rod::line([0.5, 0.0, -0.3], [0.0, 1.0, 0.0], 0.02, 5e7))
        .build()
        .unwrap()
}

fn settings() -> DynamicSettings {
    DynamicSettings {
        time_step: 1e-3,
        end_time: 0.02,
        ..Default::default()
    }
}

#[test]
fn damaged_snapshots_are_refused_naming_the_field() {
    let model = model();
    let mut sim = Simulation::new(&model, settings(), Initial::Reference).unwrap();
    for _ in 0..5 {
        sim.step().unwrap();
    }
    let good = sim.checkpoint();
    assert!(Simulation::resume(&model, settings(), good.clone()).is_ok());
    let refused = |edit: &dyn Fn(&mut Snapshot), field: &str| {
        let mut s = good.clone();
        edit(&mut s);
        let e = Simulation::resume(&model, settings(), s)
            .err()
            .expect("refused")
            .to_string();
        assert!(e.contains(field), "{field}: {e}");
    };
    refused(
        &|s| s.state.q.truncate(s.state.q.len() - 12),
        "state.q has 48 entries",
    );
    refused(&|s| s.state.v[3] = f64::NAN, "state.v[3] is not finite");
    refused(
        &|s| s.step = 999_999,
        "step 999999 is beyond the run's 20 steps",
    );
    refused(&|s| s.state.time = 0.5, "state.time = 0.5 s");
    refused(
        &|s| s.subdivision.depth = 1_000_000,
        "subdivision.depth = 1000000",
    );
    refused(
        &|s| s.rod_loads.clear(),
        "rod_loads has 0 entries, the model has 1 rods",
    );
}
