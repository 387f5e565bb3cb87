//! Procedural macros that generate ancf's unrolled element kernels.
//!
//! The crate is thin on purpose: `lib.rs` only parses and forwards; the
//! logic lives in `kernel` as functions on `proc_macro2` types, unit-tested
//! without a compiler round-trip (the nalgebra-macros pattern).

use proc_macro::TokenStream;

mod kernel;
mod mooney_rivlin;

/// Generates a quadrature-point kernel of the fully parameterized beam,
/// unrolled and specialised to the sparsity of the shape-function gradients.
///
/// ```ignore
/// ancf_macros::structured_point_kernel! {
///     /// docs…
///     pub fn point_kernel;
///     gradient_sparsity = [[x], [x], [x, y], [x, z], [x], [x], [x, y], [x, z]];
/// }
/// ```
///
/// `gradient_sparsity[i]` lists the non-zero components of ∇s_i. The
/// generated function has the signature
///
/// ```ignore
/// fn point_kernel(e: &[f64; 24], g: &[[f64; 3]; 8], w: f64, law: &crate::material::Law,
///                 q: &mut [f64; 24], k: Option<&mut [f64; 576]>) -> f64
/// ```
///
/// and adds `w ∂W/∂e` to `q`, `w ∂²W/∂e²` to `k` (row-major, full), and
/// returns `w W`. Only products of non-zero gradient components appear in
/// the code: the deformation gradient, the stress resultants, and the 8×8
/// blocks of the Jacobian, built from the 3×3 blocks H_ab = B_aᵀ D B_b + S_ab I.
#[proc_macro]
pub fn structured_point_kernel(input: TokenStream) -> TokenStream {
    match syn::parse::<kernel::KernelSpec>(input) {
        Ok(spec) => kernel::expand(&spec).into(),
        Err(e) => e.to_compile_error().into(),
    }
}

/// Generates the Mooney–Rivlin stress and tangent, unrolled, with only the
/// non-zero products of each directional derivative (see `mooney_rivlin.rs`).
///
/// ```ignore
/// ancf_macros::mooney_rivlin_kernel! { pub fn mr_stress_tangent; }
/// // fn mr_stress_tangent(eps: &Vector6<f64>, mu10, mu01, k1, k2) -> (Vector6<f64>, Matrix6<f64>)
/// ```
#[proc_macro]
pub fn mooney_rivlin_kernel(input: TokenStream) -> TokenStream {
    match syn::parse::<mooney_rivlin::MrSpec>(input) {
        Ok(spec) => mooney_rivlin::expand(&spec).into(),
        Err(e) => e.to_compile_error().into(),
    }
}
