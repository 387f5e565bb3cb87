//! Code generation for the Mooney–Rivlin stress and tangent.
//!
//! With C = I + 2E (entries `c[a][b]`), the invariants, the cofactor
//! cof = C² − I1 C + I2 I (no inverse), S = 2[μ10 I + μ01 (I1 I − C) + p cof]
//! with p = k1 + 2 k2 (I3 − 1), and for each Voigt column j the directional
//! derivative along H_j = ∂C/∂ε_j (a unit normal entry times 2, or a pair of
//! unit shear entries):
//!   dS = 2 [μ01 (tr H I − H) + 2 k2 (cof : H) cof + p dcof[H]],
//!   dcof[H] = C H + H C − tr H C − I1 H + (I1 tr H − tr(C H)) I.
//! H is sparse and known here, so only its non-zero products are emitted.

use proc_macro2::TokenStream;
use quote::quote;
use syn::parse::{Parse, ParseStream};
use syn::{Attribute, Ident, Token, Visibility};

pub struct MrSpec {
    pub attrs: Vec<Attribute>,
    pub vis: Visibility,
    pub name: Ident,
}

impl Parse for MrSpec {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let attrs = input.call(Attribute::parse_outer)?;
        let vis: Visibility = input.parse()?;
        input.parse::<Token![fn]>()?;
        let name: Ident = input.parse()?;
        let _ = input.parse::<Token![;]>();
        Ok(MrSpec { attrs, vis, name })
    }
}

const VOIGT: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];

/// Non-zero entries (a, b, value) of H_j = ∂C/∂ε_j.
pub fn perturbation(j: usize) -> Vec<(usize, usize, f64)> {
    let (p, q) = VOIGT[j];
    if p == q {
        vec![(p, p, 2.0)]
    } else {
        vec![(p, q, 1.0), (q, p, 1.0)]
    }
}

fn c(a: usize, b: usize) -> TokenStream {
    let (a, b) = (a.min(b), a.max(b));
    let id = quote::format_ident!("c{}{}", a, b);
    quote!(#id)
}

fn cof(a: usize, b: usize) -> TokenStream {
    let (a, b) = (a.min(b), a.max(b));
    let id = quote::format_ident!("f{}{}", a, b);
    quote!(#id)
}

/// Sum of terms, `0.0` when empty.
fn sum(terms: Vec<TokenStream>) -> TokenStream {
    if terms.is_empty() {
        quote!(0.0)
    } else {
        quote!((#(#terms)+*))
    }
}

/// The expression of dS_ab for column j (without the outer factor 2).
pub fn tangent_entry(a: usize, b: usize, j: usize) -> TokenStream {
    let h = perturbation(j);
    let tr_h: f64 = h.iter().filter(|(x, y, _)| x == y).map(|t| t.2).sum();
    let h_ab: f64 = h
        .iter()
        .filter(|(x, y, _)| (*x, *y) == (a, b))
        .map(|t| t.2)
        .sum();
    let delta = if a == b { 1.0 } else { 0.0 };
    let mut terms = Vec::new();
    // μ01 (tr H δ_ab − H_ab)
    let m = tr_h * delta - h_ab;
    if m != 0.0 {
        terms.push(quote!(#m * mu01));
    }
    // 2 k2 (cof : H) cof_ab
    let cof_h = sum(h
        .iter()
        .map(|&(x, y, v)| {
            let f = cof(x, y);
            quote!(#v * #f)
        })
        .collect());
    let fab = cof(a, b);
    terms.push(quote!(2.0 * k2 * #cof_h * #fab));
    // p dcof_ab: (CH)_ab + (HC)_ab − tr H C_ab − I1 H_ab + (I1 tr H − tr(CH)) δ_ab
    let mut d = Vec::new();
    for &(x, y, v) in &h {
        if y == b {
            let cc = c(a, x);
            d.push(quote!(+ #v * #cc)); // C_ax H_xb
        }
        if x == a {
            let cc = c(y, b);
            d.push(quote!(+ #v * #cc)); // H_ay C_yb
        }
    }
    if tr_h != 0.0 {
        let cc = c(a, b);
        d.push(quote!(- #tr_h * #cc));
    }
    if h_ab != 0.0 {
        d.push(quote!(- #h_ab * i1));
    }
    if delta != 0.0 {
        // tr(CH) = Σ C_yx H_xy
        let tr_ch: Vec<TokenStream> = h
            .iter()
            .map(|&(x, y, v)| {
                let cc = c(y, x);
                quote!(#v * #cc)
            })
            .collect();
        let tr_ch = sum(tr_ch);
        d.push(quote!(+ (#tr_h * i1 - #tr_ch)));
    }
    let d = quote!((0.0 #(#d)*));
    terms.push(quote!(p * #d));
    sum(terms)
}

pub fn expand(spec: &MrSpec) -> TokenStream {
    let MrSpec { attrs, vis, name } = spec;
    let mut tangent = Vec::new();
    for j in 0..6usize {
        for (r, &(a, b)) in VOIGT.iter().enumerate() {
            let e = tangent_entry(a, b, j);
            tangent.push(quote!(t[(#r, #j)] = 2.0 * #e;));
        }
    }
    let stress: Vec<TokenStream> = VOIGT
        .iter()
        .enumerate()
        .map(|(r, &(a, b))| {
            let (cab, fab) = (c(a, b), cof(a, b));
            if a == b {
                quote!(s[#r] = 2.0 * (mu10 + mu01 * (i1 - #cab) + p * #fab);)
            } else {
                quote!(s[#r] = 2.0 * (- mu01 * #cab + p * #fab);)
            }
        })
        .collect();
    quote! {
        #(#attrs)*
        #[allow(clippy::all, unused_parens, unused_variables)]
        #vis fn #name(eps: &::nalgebra::Vector6<f64>, mu10: f64, mu01: f64, k1: f64, k2: f64)
            -> (::nalgebra::Vector6<f64>, ::nalgebra::Matrix6<f64>)
        {
            // C = I + 2E; shears in eps are engineering (2E_ab).
            let c00 = 1.0 + 2.0 * eps[0];
            let c11 = 1.0 + 2.0 * eps[1];
            let c22 = 1.0 + 2.0 * eps[2];
            let c12 = eps[3];
            let c02 = eps[4];
            let c01 = eps[5];
            let i1 = c00 + c11 + c22;
            // C² (symmetric).
            let q00 = c00 * c00 + c01 * c01 + c02 * c02;
            let q11 = c01 * c01 + c11 * c11 + c12 * c12;
            let q22 = c02 * c02 + c12 * c12 + c22 * c22;
            let q01 = c00 * c01 + c01 * c11 + c02 * c12;
            let q02 = c00 * c02 + c01 * c12 + c02 * c22;
            let q12 = c01 * c02 + c11 * c12 + c12 * c22;
            let i2 = 0.5 * (i1 * i1 - (q00 + q11 + q22));
            // cof = C² − I1 C + I2 I.
            let f00 = q00 - i1 * c00 + i2;
            let f11 = q11 - i1 * c11 + i2;
            let f22 = q22 - i1 * c22 + i2;
            let f01 = q01 - i1 * c01;
            let f02 = q02 - i1 * c02;
            let f12 = q12 - i1 * c12;
            let i3 = c00 * f00 + c01 * f01 + c02 * f02;
            let p = k1 + 2.0 * k2 * (i3 - 1.0);
            let mut s = ::nalgebra::Vector6::<f64>::zeros();
            #(#stress)*
            let mut t = ::nalgebra::Matrix6::<f64>::zeros();
            #(#tangent)*
            (s, t)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perturbations_are_the_voigt_unit_directions() {
        assert_eq!(perturbation(0), vec![(0, 0, 2.0)]);
        assert_eq!(perturbation(3), vec![(1, 2, 1.0), (2, 1, 1.0)]);
    }

    #[test]
    fn zero_products_are_not_emitted() {
        // dS_00 along a 12-shear: H has no (0, x) entries, so no C H or H C term.
        let code = tangent_entry(0, 0, 3).to_string();
        assert!(!code.contains("- 1f64 * i1"), "{code}");
        assert!(code.contains("f12"), "cof : H uses cof_12: {code}");
        // dS_11 along ε_11: C H, H C, −tr H C and tr(C H) each contribute C_11 once.
        let code = tangent_entry(1, 1, 1).to_string();
        assert_eq!(code.matches("c11").count(), 4, "{code}");
        // dS_00 along ε_11: H = 2 e₁e₁ has no row or column 0, so no C H or H C term.
        let code = tangent_entry(0, 0, 1).to_string();
        assert!(!code.contains("c01") && !code.contains("c02"), "{code}");
    }

    #[test]
    fn expands_to_a_function() {
        let spec: MrSpec = syn::parse2(quote!(pub fn mr;)).unwrap();
        let code = expand(&spec).to_string();
        assert!(code.contains("fn mr"));
        assert_eq!(code.matches("t [(").count(), 36);
    }
}
