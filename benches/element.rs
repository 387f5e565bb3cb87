//! Element kernel timings: force and Jacobian per element,
//! generated vs generic, for (a) a rectangle with 3 axial × 2×2 section
//! points and (b) a two-layer circle, 3 axial points, ring rule n = 3.
//! Run: `cargo bench --bench element`

use ancf::bench::{deformed_element, rubber, svk};
use ancf_core::element::ElementIntegration;
use ancf_core::material::Material;
use ancf_core::section::Section;
use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;

/// The bench's cover: `ancf bench`'s rubber with the default locking remedy.
fn mooney_rivlin() -> Material {
    Material {
        locking: Default::default(),
        yield_stress: None,
        ..rubber()
    }
}

fn bench(c: &mut Criterion) {
    let l = 0.25;
    let cases = [
        (
            "rect_3x2x2_svk",
            Section::rectangular(0.02, 0.02, svk(0.3), 2),
        ),
        (
            "circle2_3xn3_svk",
            Section::circular(&[(0.0, 0.01, svk(0.3)), (0.01, 0.02, svk(0.3))], 3),
        ),
        (
            "circle2_3xn3_svk_mr",
            Section::circular(&[(0.0, 0.01, svk(0.3)), (0.01, 0.02, mooney_rivlin())], 3),
        ),
        // `ancf bench`'s per-point Mooney–Rivlin case (plain formulation).
        (
            "circle1_3xn3_mr_plain",
            Section::circular(&[(0.0, 0.02, rubber())], 3),
        ),
    ];
    let e = deformed_element(l);
    for (name, section) in cases {
        let generated = ElementIntegration::new(l, 3, section);
        let generic = generated.clone().with_generic_kernel();
        for (path, el) in [("generated", &generated), ("generic", &generic)] {
            c.bench_function(&format!("{name}/{path}/force"), |b| {
                b.iter(|| {
                    let mut q = [0.0; 24];
                    black_box(el.evaluate(black_box(&e), &mut q, None));
                    q
                })
            });
            c.bench_function(&format!("{name}/{path}/jacobian"), |b| {
                let mut k = [0.0; 576];
                b.iter(|| {
                    let mut q = [0.0; 24];
                    k.fill(0.0);
                    black_box(el.evaluate(black_box(&e), &mut q, Some(&mut k)));
                    black_box(k[0])
                })
            });
        }
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).measurement_time(std::time::Duration::from_secs(2)).warm_up_time(std::time::Duration::from_millis(500));
    targets = bench
}
criterion_main!(benches);
