//! Code generation for the structured point kernel (see the crate docs).
//!
//! Notation of the generated code: `e` the element coordinates (node i,
//! direction k at `e[3i + k]`), `g[i][a]` the gradient ∇s_i, `f[k][a]` the
//! deformation gradient, σ/`d` the law's stress and tangent in Voigt form.

use proc_macro2::TokenStream;
use quote::quote;
use syn::parse::{Parse, ParseStream};
use syn::{Attribute, Ident, Token, Visibility, bracketed};

/// What the macro was asked for.
pub struct KernelSpec {
    pub attrs: Vec<Attribute>,
    pub vis: Visibility,
    pub name: Ident,
    /// For each shape function, the non-zero gradient components (0 = x, 1 = y, 2 = z).
    pub sparsity: Vec<Vec<usize>>,
}

fn axis(ident: &Ident) -> syn::Result<usize> {
    match ident.to_string().as_str() {
        "x" => Ok(0),
        "y" => Ok(1),
        "z" => Ok(2),
        _ => Err(syn::Error::new(
            ident.span(),
            "a gradient component is one of x, y, z",
        )),
    }
}

impl Parse for KernelSpec {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let attrs = input.call(Attribute::parse_outer)?;
        let vis: Visibility = input.parse()?;
        input.parse::<Token![fn]>()?;
        let name: Ident = input.parse()?;
        input.parse::<Token![;]>()?;
        let key: Ident = input.parse()?;
        if key != "gradient_sparsity" {
            return Err(syn::Error::new(
                key.span(),
                "expected `gradient_sparsity = [...]`",
            ));
        }
        input.parse::<Token![=]>()?;
        let outer;
        bracketed!(outer in input);
        let mut sparsity = Vec::new();
        while !outer.is_empty() {
            let inner;
            bracketed!(inner in outer);
            let comps = inner.parse_terminated(Ident::parse, Token![,])?;
            let mut row = Vec::new();
            for c in &comps {
                row.push(axis(c)?);
            }
            sparsity.push(row);
            if !outer.is_empty() {
                outer.parse::<Token![,]>()?;
            }
        }
        let _ = input.parse::<Token![;]>();
        if sparsity.len() != 8 {
            return Err(syn::Error::new(
                name.span(),
                "the beam element has 8 shape functions",
            ));
        }
        Ok(KernelSpec {
            attrs,
            vis,
            name,
            sparsity,
        })
    }
}

/// Voigt index pairs; must match `ancf_core::material::VOIGT`.
const VOIGT: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];

/// Non-zero entries of column k of B_a (∂ε/∂F_ka): (Voigt row, F column c)
/// meaning B_a[row, k] = F[k][c].
pub fn basis_nonzeros(a: usize) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for (row, &(p, q)) in VOIGT.iter().enumerate() {
        // ε_row = ½ c_pp (p = q) or c_pq; ∂c_pq/∂F_ka = δ_ap F_kq + δ_aq F_kp.
        if p == q {
            if a == p {
                out.push((row, p));
            }
        } else {
            if a == p {
                out.push((row, q));
            }
            if a == q {
                out.push((row, p));
            }
        }
    }
    out
}

/// The expression for F[k][a] = Σ_i e[3i + k] g[i][a] over the non-zero g only.
pub fn deformation_gradient_entry(sparsity: &[Vec<usize>], k: usize, a: usize) -> TokenStream {
    let terms: Vec<TokenStream> = sparsity
        .iter()
        .enumerate()
        .filter(|(_, nz)| nz.contains(&a))
        .map(|(i, _)| {
            let idx = 3 * i + k;
            quote!(e[#idx] * g[#i][#a])
        })
        .collect();
    if terms.is_empty() {
        quote!(0.0)
    } else {
        quote!(#(#terms)+*)
    }
}

/// The (a, b) pairs that contribute to the Jacobian block of nodes (i, j).
pub fn block_pairs(sparsity: &[Vec<usize>], i: usize, j: usize) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for &a in &sparsity[i] {
        for &b in &sparsity[j] {
            out.push((a, b));
        }
    }
    out
}

/// The whole kernel.
pub fn expand(spec: &KernelSpec) -> TokenStream {
    let KernelSpec {
        attrs,
        vis,
        name,
        sparsity,
    } = spec;
    let n = sparsity.len();

    // Deformation gradient.
    let mut f_stmts = Vec::new();
    for k in 0..3usize {
        for a in 0..3usize {
            let expr = deformation_gradient_entry(sparsity, k, a);
            f_stmts.push(quote!(f[#k][#a] = #expr;));
        }
    }

    // Green–Lagrange strain in Voigt form.
    let eps_stmts: Vec<TokenStream> = VOIGT
        .iter()
        .enumerate()
        .map(|(r, &(p, q))| {
            let dot = quote!(f[0][#p] * f[0][#q] + f[1][#p] * f[1][#q] + f[2][#p] * f[2][#q]);
            if p == q {
                quote!(eps[#r] = 0.5 * (#dot - 1.0);)
            } else {
                quote!(eps[#r] = #dot;)
            }
        })
        .collect();

    // Stress resultants P[k][a] = (F S)[k][a] = B_a[:, k] · σ, then q_i.
    let mut p_stmts = Vec::new();
    for a in 0..3usize {
        for k in 0..3usize {
            let terms: Vec<TokenStream> = basis_nonzeros(a)
                .iter()
                .map(|&(row, c)| quote!(f[#k][#c] * sigma[#row]))
                .collect();
            p_stmts.push(quote!(p[#k][#a] = #(#terms)+*;));
        }
    }
    let mut q_stmts = Vec::new();
    for (i, nz) in sparsity.iter().enumerate() {
        for k in 0..3usize {
            let idx = 3 * i + k;
            let terms: Vec<TokenStream> =
                nz.iter().map(|&a| quote!(g[#i][#a] * p[#k][#a])).collect();
            q_stmts.push(quote!(q[#idx] += w * (#(#terms)+*);));
        }
    }

    // D B_b, then H_ab = B_aᵀ D B_b + S_ab I, only for the axis pairs used.
    let used: Vec<(usize, usize)> = {
        let mut u = Vec::new();
        for i in 0..n {
            for j in i..n {
                for pair in block_pairs(sparsity, i, j) {
                    if !u.contains(&pair) {
                        u.push(pair);
                    }
                }
            }
        }
        u
    };
    let mut used_b: Vec<usize> = used.iter().map(|p| p.1).collect();
    used_b.sort_unstable();
    used_b.dedup();
    let mut db_stmts = Vec::new();
    for &b in &used_b {
        for m in 0..3usize {
            for r in 0..6usize {
                let terms: Vec<TokenStream> = basis_nonzeros(b)
                    .iter()
                    .map(|&(row, c)| quote!(d[(#r, #row)] * f[#m][#c]))
                    .collect();
                db_stmts.push(quote!(db[#b][#r][#m] = #(#terms)+*;));
            }
        }
    }
    let voigt_of = |p: usize, q: usize| -> usize {
        VOIGT
            .iter()
            .position(|&(a, b)| (a, b) == (p.min(q), p.max(q)))
            .unwrap()
    };
    let mut h_stmts = Vec::new();
    // H_ba = H_abᵀ: computed once, the other copied (computed first: `used`
    // is visited with a ≤ b before its mirror).
    let mut used = used;
    used.sort_by_key(|&(a, b)| (a > b, a, b));
    for &(a, b) in &used {
        if a > b && used.contains(&(b, a)) {
            for k in 0..3usize {
                for m in 0..3usize {
                    h_stmts.push(quote!(h[#a][#b][#k][#m] = h[#b][#a][#m][#k];));
                }
            }
            continue;
        }
        let s_ab = voigt_of(a, b);
        for k in 0..3usize {
            for m in 0..3usize {
                let terms: Vec<TokenStream> = basis_nonzeros(a)
                    .iter()
                    .map(|&(row, c)| quote!(f[#k][#c] * db[#b][#row][#m]))
                    .collect();
                let geo = if k == m {
                    quote!(+ sigma[#s_ab])
                } else {
                    quote!()
                };
                h_stmts.push(quote!(h[#a][#b][#k][#m] = #(#terms)+* #geo;));
            }
        }
    }

    // Jacobian: the upper triangle (row ≤ column) only; the caller mirrors
    // it once per element (writing the mirror at every point doubled the
    // kernel's memory traffic).
    let mut k_stmts = Vec::new();
    for i in 0..n {
        for j in i..n {
            let pairs = block_pairs(sparsity, i, j);
            for kk in 0..3usize {
                for m in 0..3usize {
                    let terms: Vec<TokenStream> = pairs
                        .iter()
                        .map(|&(a, b)| quote!(g[#i][#a] * g[#j][#b] * h[#a][#b][#kk][#m]))
                        .collect();
                    let row = 3 * i + kk;
                    let col = 3 * j + m;
                    let at = row * 24 + col;
                    if i != j || m >= kk {
                        k_stmts.push(quote!(k[#at] += w * (#(#terms)+*);));
                    }
                }
            }
        }
    }

    quote! {
        #(#attrs)*
        #[allow(clippy::all, unused_parens)]
        #[inline]
        #vis fn #name(
            e: &[f64; 24],
            g: &[[f64; 3]; 8],
            w: f64,
            law: &crate::material::Law,
            q: &mut [f64; 24],
            k: ::core::option::Option<&mut [f64; 576]>,
        ) -> f64 {
            let mut f = [[0.0f64; 3]; 3];
            #(#f_stmts)*
            let mut eps = ::nalgebra::Vector6::<f64>::zeros();
            #(#eps_stmts)*
            let mut p = [[0.0f64; 3]; 3];
            let energy;
            match k {
                ::core::option::Option::None => {
                    let sigma = law.stress(&eps);
                    energy = w * law.energy(&eps);
                    #(#p_stmts)*
                    #(#q_stmts)*
                }
                ::core::option::Option::Some(k) => {
                    let st = law.stress_tangent(&eps);
                    let sigma = st.stress;
                    let d = st.tangent;
                    energy = w * law.energy(&eps);
                    #(#p_stmts)*
                    #(#q_stmts)*
                    let mut db = [[[0.0f64; 3]; 6]; 3];
                    #(#db_stmts)*
                    let mut h = [[[[0.0f64; 3]; 3]; 3]; 3];
                    #(#h_stmts)*
                    #(#k_stmts)*
                }
            }
            energy
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn beam_sparsity() -> Vec<Vec<usize>> {
        vec![
            vec![0],
            vec![0],
            vec![0, 1],
            vec![0, 2],
            vec![0],
            vec![0],
            vec![0, 1],
            vec![0, 2],
        ]
    }

    #[test]
    fn parses_the_beam_pattern() {
        let spec: KernelSpec = syn::parse2(quote! {
            /// doc
            pub fn kern;
            gradient_sparsity = [[x], [x], [x, y], [x, z], [x], [x], [x, y], [x, z]];
        })
        .unwrap();
        assert_eq!(spec.name, "kern");
        assert_eq!(spec.sparsity, beam_sparsity());
        assert_eq!(spec.attrs.len(), 1);
    }

    #[test]
    fn rejects_unknown_axis_and_wrong_count() {
        let bad_axis = syn::parse2::<KernelSpec>(quote! { fn k; gradient_sparsity = [[w]]; });
        assert!(bad_axis.is_err());
        let short = syn::parse2::<KernelSpec>(quote! { fn k; gradient_sparsity = [[x], [y]]; });
        assert!(
            short
                .err()
                .unwrap()
                .to_string()
                .contains("8 shape functions")
        );
    }

    #[test]
    fn basis_columns_have_three_nonzeros() {
        // B_x[:, k] = [F_k0, 0, 0, 0, F_k2, F_k1]
        assert_eq!(basis_nonzeros(0), vec![(0, 0), (4, 2), (5, 1)]);
        assert_eq!(basis_nonzeros(1), vec![(1, 1), (3, 2), (5, 0)]);
        assert_eq!(basis_nonzeros(2), vec![(2, 2), (3, 1), (4, 0)]);
    }

    #[test]
    fn deformation_gradient_skips_zero_gradients() {
        let s = beam_sparsity();
        // r_y (column 1) depends only on nodes 3 and 7 (indices 2 and 6).
        let ry = deformation_gradient_entry(&s, 0, 1).to_string();
        assert_eq!(ry.matches("e [").count(), 2, "{ry}");
        assert!(
            ry.contains("e [6usize]") && ry.contains("e [18usize]"),
            "{ry}"
        );
        // r_x involves all eight.
        assert_eq!(
            deformation_gradient_entry(&s, 2, 0)
                .to_string()
                .matches("e [")
                .count(),
            8
        );
    }

    #[test]
    fn axial_node_blocks_use_one_term() {
        let s = beam_sparsity();
        assert_eq!(block_pairs(&s, 0, 1), vec![(0, 0)]);
        assert_eq!(block_pairs(&s, 2, 3), vec![(0, 0), (0, 2), (1, 0), (1, 2)]);
        let code = expand(
            &syn::parse2(quote! {
                fn kern; gradient_sparsity = [[x], [x], [x, y], [x, z], [x], [x], [x, y], [x, z]];
            })
            .unwrap(),
        )
        .to_string();
        // H_yz and H_zy are needed (nodes 3 and 4), H_yy and H_zz too.
        assert!(code.contains("h [1usize] [2usize]"));
        assert!(code.contains("fn kern"));
    }
}
