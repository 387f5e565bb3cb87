//! Broyden's rank-one updates of the kept Newton matrix within a step.
//!
//! Modified Newton solves with a factorization B₀ formed at an earlier
//! iterate (often an earlier step). Where the true Jacobian has moved away
//! from it (contact stiffness switching, the wire's geometric stiffness
//! after an impact), the iteration contracts linearly, and slowly: on the
//! span break after its first impacts by 0.3–0.5 per iteration, which
//! forces a refactorization in about half the steps. "Good" Broyden
//! updates B₀ by one rank per iteration from the steps taken and the
//! residuals seen, without forming a matrix: each direction is the plain
//! solve B₀⁻¹R corrected by the steps of the current sequence, the
//! Sherman–Morrison recursion of Kelley (1995), *Iterative Methods for
//! Linear and Nonlinear Equations*, SIAM, §7.3 (Algorithm `brsol`). The
//! corrections cost a few dot products and vector updates per stored step;
//! no factorization changes, and the sequence restarts whenever the matrix
//! is refactored or a step is shortened by backtracking (the recursion
//! assumes full steps).

use crate::math::simd::{Plain, dot};

/// The Newton directions taken since the sequence restarted, in the
/// increment's sign convention (aₖ₊₁ = aₖ − dₖ), with their buffers kept
/// across steps (no allocation once the longest sequence has been seen),
/// and their squared norms ‖dₖ‖², computed once.
#[derive(Default)]
pub(super) struct Broyden {
    steps: Vec<Vec<f64>>,
    squares: Vec<f64>,
    len: usize,
}

/// Below this |1 − sₙ·z/‖sₙ‖²| the rank-one update is near singular (the
/// last step barely reduced the residual): the sequence restarts instead.
const BREAKDOWN: f64 = 0.1;

impl Broyden {
    /// Forgets the sequence: the next direction is the plain solve.
    pub(super) fn restart(&mut self) {
        self.len = 0;
    }

    /// Turns the plain solve `d` = B₀⁻¹R(aₙ) into the Broyden direction at
    /// aₙ and records it, the previous directions having been taken in
    /// full. With no previous direction (or at a breakdown) `d` stays the
    /// plain solve and starts a new sequence.
    pub(super) fn direct(&mut self, d: &mut [f64]) {
        if self.len == self.steps.len() {
            self.steps.push(vec![0.0; d.len()]);
            self.squares.push(0.0);
        }
        let (done, next) = self.steps.split_at_mut(self.len);
        let plain = &mut next[0];
        plain.clear();
        plain.extend_from_slice(d);
        let squares = &self.squares[..self.len];
        if let Some(last) = done.last() {
            for (pair, square) in done.windows(2).zip(squares) {
                let c = dot::<Plain>(&pair[0], d) / square;
                d.iter_mut().zip(&pair[1]).for_each(|(z, s)| *z += c * s);
            }
            let den = 1.0 - dot::<Plain>(last, d) / squares[self.len - 1];
            if den.abs() >= BREAKDOWN && den.is_finite() {
                d.iter_mut().for_each(|z| *z /= den);
                plain.copy_from_slice(d);
                self.squares[self.len] = dot::<Plain>(d, d);
                self.len += 1;
                return;
            }
            // Breakdown: the plain solve starts a new sequence.
            d.copy_from_slice(plain);
            self.steps.swap(0, self.len);
        }
        self.squares[0] = dot::<Plain>(d, d);
        self.len = 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    /// A linear system A x = b solved from x = 0 with a kept matrix B₀ ≠ A,
    /// the plain way (dₖ = B₀⁻¹ rₖ) or with Broyden's directions; the
    /// iterations until ‖r‖ ≤ 1e-12 ‖b‖.
    fn iterations(a: &DMatrix<f64>, b0: &DMatrix<f64>, b: &DVector<f64>, broyden: bool) -> usize {
        let lu = b0.clone().lu();
        let mut x = DVector::zeros(b.len());
        let mut seq = Broyden::default();
        for k in 0..200 {
            let r = a * &x - b;
            if r.norm() <= 1e-12 * b.norm() {
                return k;
            }
            let mut d = lu.solve(&r).unwrap();
            if broyden {
                seq.direct(d.as_mut_slice());
            }
            x -= d;
        }
        usize::MAX
    }

    /// A symmetric positive matrix of size n and a kept matrix that misses
    /// part of it (a stale stiffness): B₀ = A − the coupling's 40 %.
    fn system(n: usize) -> (DMatrix<f64>, DMatrix<f64>, DVector<f64>) {
        let a = DMatrix::from_fn(n, n, |i, j| match i.abs_diff(j) {
            0 => 4.0 + 0.1 * i as f64,
            1 => -1.0,
            2 => 0.3,
            _ => 0.0,
        });
        let b0 = DMatrix::from_fn(
            n,
            n,
            |i, j| if i == j { a[(i, j)] } else { 0.6 * a[(i, j)] },
        );
        let b = DVector::from_fn(n, |i, _| (i as f64 * 0.7).sin() + 1.0);
        (a, b0, b)
    }

    #[test]
    fn broyden_solves_a_linear_system_within_2n_iterations_and_faster_than_the_kept_matrix() {
        // Gay (1979): on a linear system Broyden's method ends in at most
        // 2n steps; the plain iteration contracts only linearly.
        let n = 12;
        let (a, b0, b) = system(n);
        let plain = iterations(&a, &b0, &b, false);
        let updated = iterations(&a, &b0, &b, true);
        assert!(plain < 200, "the kept matrix alone converges ({plain})");
        assert!(
            updated <= 2 * n,
            "Broyden took {updated} iterations for n = {n}"
        );
        assert!(
            updated < plain,
            "Broyden {updated} against the kept matrix {plain}"
        );
    }

    #[test]
    fn with_the_exact_matrix_one_step_solves_a_linear_system() {
        // B₀ = A: the first direction is the plain Newton step.
        let (a, _, b) = system(8);
        assert_eq!(iterations(&a, &a, &b, true), 1);
    }

    #[test]
    fn restart_makes_the_next_direction_the_plain_solve() {
        let plain = vec![0.5, -1.0, 0.25];
        // After a direction, the next solve is corrected…
        let mut seq = Broyden::default();
        seq.direct(&mut [1.0, 2.0, 3.0]);
        let mut e = plain.clone();
        seq.direct(&mut e);
        assert_ne!(e, plain);
        // …after a restart it is not.
        seq.restart();
        seq.direct(&mut [1.0, 2.0, 3.0]);
        seq.restart();
        let mut e = plain.clone();
        seq.direct(&mut e);
        assert_eq!(e, plain);
    }

    #[test]
    fn a_step_that_did_not_help_restarts_the_sequence() {
        // z = the last step: 1 − s·z/‖s‖² = 0, the update would divide by 0.
        let mut seq = Broyden::default();
        let mut d = vec![1.0, 2.0, 3.0];
        seq.direct(&mut d);
        let mut again = vec![1.0, 2.0, 3.0];
        seq.direct(&mut again);
        assert_eq!(again, vec![1.0, 2.0, 3.0]);
        assert_eq!(seq.len, 1);
    }
}
