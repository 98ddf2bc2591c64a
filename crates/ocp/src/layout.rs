//! Variable layout of the Radau transcription (v2, FORMULATION 8.3 and Appendix B).
//!
//! Order of the NLP vector (the reference's declaration order, which fixes the pivot order
//! of the sparse factorisation): t_f; activations at mesh points 0..N, then at the 3N
//! collocation points; normalised tendon forces (mesh, collocation); coordinates (mesh,
//! collocation); speeds (mesh, collocation); arm activations (mesh, collocation); activation
//! derivatives per interval; arm excitations per interval; tendon-force derivatives per
//! collocation point; accelerations per collocation point. Within a block, the values of
//! one point are contiguous.

use stride_solve::nlp::BlockStructure;

/// Sizes of one problem and the offsets of every variable block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Mesh intervals N.
    pub n: usize,
    /// Muscles.
    pub nm: usize,
    /// Free coordinates.
    pub nq: usize,
    /// Arm (actuator-driven) coordinates.
    pub na: usize,
    a_mesh: usize,
    a_col: usize,
    f_mesh: usize,
    f_col: usize,
    q_mesh: usize,
    q_col: usize,
    v_mesh: usize,
    v_col: usize,
    arm_mesh: usize,
    arm_col: usize,
    u_da: usize,
    e_arm: usize,
    u_df: usize,
    u_dv: usize,
    total: usize,
}

/// A point of the mesh: mesh point `k` (0..=N) or collocation point `j` (1..=3) of interval `k`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Point {
    /// Mesh point k (0..=N).
    Mesh(usize),
    /// Collocation point j (1..=3) of interval k (0..N).
    Col(usize, usize),
}

impl Layout {
    /// Layout for N intervals, `nm` muscles, `nq` coordinates, `na` arm actuators.
    pub fn new(n: usize, nm: usize, nq: usize, na: usize) -> Self {
        let mesh = n + 1;
        let col = 3 * n;
        let mut o = 1; // t_f
        let mut take = |len: usize| {
            let start = o;
            o += len;
            start
        };
        let a_mesh = take(nm * mesh);
        let a_col = take(nm * col);
        let f_mesh = take(nm * mesh);
        let f_col = take(nm * col);
        let q_mesh = take(nq * mesh);
        let q_col = take(nq * col);
        let v_mesh = take(nq * mesh);
        let v_col = take(nq * col);
        let arm_mesh = take(na * mesh);
        let arm_col = take(na * col);
        let u_da = take(nm * n);
        let e_arm = take(na * n);
        let u_df = take(nm * col);
        let u_dv = take(nq * col);
        Self {
            n,
            nm,
            nq,
            na,
            a_mesh,
            a_col,
            f_mesh,
            f_col,
            q_mesh,
            q_col,
            v_mesh,
            v_col,
            arm_mesh,
            arm_col,
            u_da,
            e_arm,
            u_df,
            u_dv,
            total: o,
        }
    }

    /// Total number of NLP variables.
    pub fn len(&self) -> usize {
        self.total
    }
    /// Whether the layout is empty (never: t_f always exists).
    pub fn is_empty(&self) -> bool {
        false
    }
    /// Index of the duration t_f [s].
    pub fn tf(&self) -> usize {
        0
    }
    fn at(&self, mesh_base: usize, col_base: usize, width: usize, p: Point, i: usize) -> usize {
        debug_assert!(i < width);
        match p {
            Point::Mesh(k) => mesh_base + k * width + i,
            Point::Col(k, j) => col_base + (3 * k + j - 1) * width + i,
        }
    }
    /// Activation of muscle `m` at point `p`.
    pub fn a(&self, p: Point, m: usize) -> usize {
        self.at(self.a_mesh, self.a_col, self.nm, p, m)
    }
    /// Scaled normalised tendon force of muscle `m` at point `p`.
    pub fn f(&self, p: Point, m: usize) -> usize {
        self.at(self.f_mesh, self.f_col, self.nm, p, m)
    }
    /// Scaled coordinate `i` at point `p`.
    pub fn q(&self, p: Point, i: usize) -> usize {
        self.at(self.q_mesh, self.q_col, self.nq, p, i)
    }
    /// Scaled speed `i` at point `p`.
    pub fn v(&self, p: Point, i: usize) -> usize {
        self.at(self.v_mesh, self.v_col, self.nq, p, i)
    }
    /// Arm activation `i` at point `p`.
    pub fn arm(&self, p: Point, i: usize) -> usize {
        self.at(self.arm_mesh, self.arm_col, self.na, p, i)
    }
    /// Scaled activation derivative of muscle `m` on interval `k`.
    pub fn u_da(&self, k: usize, m: usize) -> usize {
        self.u_da + k * self.nm + m
    }
    /// Arm excitation `i` on interval `k`.
    pub fn e_arm(&self, k: usize, i: usize) -> usize {
        self.e_arm + k * self.na + i
    }
    /// Scaled tendon-force derivative of muscle `m` at collocation point (k, j).
    pub fn u_df(&self, k: usize, j: usize, m: usize) -> usize {
        self.u_df + (3 * k + j - 1) * self.nm + m
    }
    /// Scaled acceleration `i` at collocation point (k, j).
    pub fn u_dv(&self, k: usize, j: usize, i: usize) -> usize {
        self.u_dv + (3 * k + j - 1) * self.nq + i
    }
    /// Number of state components per point (a, F̃_T, q, v, a_arm).
    pub fn n_states(&self) -> usize {
        2 * self.nm + 2 * self.nq + self.na
    }
    /// The chain of mesh intervals for the KKT ordering: interval k owns the states of mesh
    /// point k and of its collocation points and its controls; the last interval also owns
    /// the final mesh point; t_f is global.
    pub fn interval_blocks(&self) -> BlockStructure {
        let blocks = (0..self.n)
            .map(|k| {
                let mut vars = Vec::new();
                let mut points = vec![Point::Mesh(k)];
                points.extend((1..=3).map(|j| Point::Col(k, j)));
                if k + 1 == self.n {
                    points.push(Point::Mesh(self.n));
                }
                for p in points {
                    vars.extend((0..self.n_states()).map(|s| self.state(p, s)));
                }
                vars.extend((0..self.nm).map(|m| self.u_da(k, m)));
                vars.extend((0..self.na).map(|i| self.e_arm(k, i)));
                for j in 1..=3 {
                    vars.extend((0..self.nm).map(|m| self.u_df(k, j, m)));
                    vars.extend((0..self.nq).map(|i| self.u_dv(k, j, i)));
                }
                vars
            })
            .collect();
        BlockStructure {
            blocks,
            global_variables: vec![self.tf()],
        }
    }
    /// Index of state component `s` (in the order a, F, q, v, arm) at point `p`.
    pub fn state(&self, p: Point, s: usize) -> usize {
        let (nm, nq) = (self.nm, self.nq);
        if s < nm {
            self.a(p, s)
        } else if s < 2 * nm {
            self.f(p, s - nm)
        } else if s < 2 * nm + nq {
            self.q(p, s - 2 * nm)
        } else if s < 2 * nm + 2 * nq {
            self.v(p, s - 2 * nm - nq)
        } else {
            self.arm(p, s - 2 * nm - 2 * nq)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nominal_problem_has_73401_variables() {
        let l = Layout::new(50, 92, 29, 8);
        assert_eq!(l.len(), 73_401);
    }

    #[test]
    fn interval_blocks_cover_every_variable_once() {
        let l = Layout::new(4, 3, 5, 2);
        let b = l.interval_blocks();
        assert_eq!(b.blocks.len(), 4);
        let mut count = vec![0usize; l.len()];
        for v in b.blocks.iter().flatten().chain(&b.global_variables) {
            count[*v] += 1;
        }
        assert!(count.iter().all(|&c| c == 1), "{count:?}");
        // interval 1 owns mesh point 1 and the controls of interval 1, not mesh point 2
        assert!(b.blocks[1].contains(&l.q(Point::Mesh(1), 0)));
        assert!(b.blocks[1].contains(&l.u_da(1, 2)));
        assert!(b.blocks[2].contains(&l.q(Point::Mesh(2), 0)));
        assert!(b.blocks[3].contains(&l.v(Point::Mesh(4), 4)));
    }

    #[test]
    fn indices_are_a_bijection() {
        let l = Layout::new(3, 4, 5, 2);
        let mut seen = vec![false; l.len()];
        let mut mark = |i: usize| {
            assert!(!seen[i], "index {i} used twice");
            seen[i] = true;
        };
        mark(l.tf());
        let mut points: Vec<Point> = (0..=l.n).map(Point::Mesh).collect();
        for k in 0..l.n {
            for j in 1..=3 {
                points.push(Point::Col(k, j));
            }
        }
        for &p in &points {
            for s in 0..l.n_states() {
                mark(l.state(p, s));
            }
        }
        for k in 0..l.n {
            (0..l.nm).for_each(|m| mark(l.u_da(k, m)));
            (0..l.na).for_each(|i| mark(l.e_arm(k, i)));
            for j in 1..=3 {
                (0..l.nm).for_each(|m| mark(l.u_df(k, j, m)));
                (0..l.nq).for_each(|i| mark(l.u_dv(k, j, i)));
            }
        }
        assert!(seen.iter().all(|&s| s));
    }
}
