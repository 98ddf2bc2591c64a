//! Sparse derivative propagation over statically known per-node index sets.
#![allow(clippy::needless_range_loop)]
//!
//! - Jacobian: forward mode where node `k` carries its gradient only on its input set
//!   `P(k)` (known at record time); each operation scatters its operands' gradients
//!   through precomputed position maps. Cost `Σₖ |P(args)|` instead of `n` per node.
//! - Hessian of `Σ λᵢ yᵢ`: second-order adjoint `ȧₖ = ∂āₖ/∂x` carried on its static set
//!   `R(k)` and propagated in reverse, `ȧₐ += ∂ₐφ ȧₖ + āₖ (∂²ₐₐφ ∇a + ∂²ₐᵦφ ∇b)`, using the
//!   sparse gradients `∇a` of the forward pass. Row `i` of the Hessian is `ȧ` of input `i`.
//! - Linear combinations: a chain or tree of operations with constant partials (sums,
//!   differences, scalings) whose intermediate results are used once, by the next such
//!   operation, is swept as one `Σ cⱼ ∇j` at its root; the intermediates store neither
//!   `P` nor `R` entries (a sum of n terms costs O(n·|P(root)|) instead of O(n²)).
//! - Product folding (forward sweep only): an operation with variable partials (a
//!   product, a quotient, a unary function) whose result is used once, by a linear
//!   combination, stores no `P` either; its operands join the combination as terms whose
//!   coefficient is the constant path coefficient times the operation's local partial
//!   at the evaluation point. The reverse sweep still stores its `R` set, since its
//!   curvature terms need it.

use super::op::{Curvature, Op};
use super::slots::Slots;
use crate::sparsity::{bits, BitSets, Pattern};

/// Where the entries of a source index set land in a destination index set.
#[derive(Clone, Copy, Debug, Default)]
struct Map {
    /// Offset of the positions in the map store (unused when `ident`).
    off: u32,
    /// Source and destination sets are equal: positions are the identity.
    ident: bool,
}

/// Per-operation maps of the sparse sweeps.
#[derive(Clone, Copy, Debug, Default)]
struct OpMaps {
    /// `P(a) → P(k)` and `P(b) → P(k)` (forward gradients).
    fa: Map,
    fb: Map,
    /// `R(k) → R(a)`, `R(k) → R(b)` (first-order part of the second-order adjoint).
    ra: Map,
    rb: Map,
    /// `P(a) → R(a)`, `P(b) → R(a)`, `P(a) → R(b)`, `P(b) → R(b)` (curvature terms).
    pa_ra: Map,
    pb_ra: Map,
    pa_rb: Map,
    pb_rb: Map,
}

/// One active operation of the forward gradient sweep, with every offset it needs laid
/// out together so that the sweep reads its instructions sequentially.
#[derive(Clone, Copy, Debug)]
struct FwdStep {
    /// Operation index (row of the local partials).
    t: u32,
    /// Start and length of `P(k)` in the gradient store.
    k: u32,
    k_len: u32,
    /// Start and length of `P(a)`, `P(b)` (length 0: operand without derivative).
    a: u32,
    a_len: u32,
    b: u32,
    b_len: u32,
    /// `P(a) → P(k)`, `P(b) → P(k)`.
    fa: Map,
    fb: Map,
    /// Both operands are the same node (`x * x`): one scatter with the summed partials.
    same: bool,
    /// A collapsed linear combination (non-empty): `P(k)` is the sum of these terms of
    /// `SparsePlan::terms` instead of the two operands.
    terms: Span,
}

/// A forward gradient sweep: its steps, the terms of their collapsed combinations, and
/// where in its store the inputs' unit seeds go and the outputs' gradients end up.
#[derive(Clone, Debug, Default)]
pub(super) struct FwdPlan {
    /// Active, stored operations in ascending order.
    steps: Vec<FwdStep>,
    /// Terms of the collapsed linear combinations of `steps`.
    terms: Vec<Term>,
    /// Places of the inputs' gradients (each the single entry 1).
    seeds: Vec<u32>,
    /// `P(o)` of each output, in output order.
    outputs: Vec<Span>,
    /// Length of the store.
    len: u32,
    /// For the sweep fused with the values ([`super::Tape::value_gradient_sweep`]): the
    /// place of each operation's partials in the store of kept partials (`u32::MAX`: not
    /// kept; only folded operations' partials, which a later combination's terms read,
    /// are), and that store's length. The terms' `w.part` then name places in it.
    save: Vec<u32>,
    saved_len: u32,
}

impl FwdPlan {
    /// Checks what the sweep's unchecked accesses rely on: every set lies within the
    /// store, and no set a step reads overlaps the set it writes.
    fn check_places(&self) {
        let inside = |s: Span| s.start as usize + s.len as usize <= self.len as usize;
        let apart = |s: Span, k: Span| {
            s.len == 0 || s.start + s.len <= k.start || s.start >= k.start + k.len
        };
        for s in &self.steps {
            let k = Span {
                start: s.k,
                len: s.k_len,
            };
            let operands = [(s.a, s.a_len), (s.b, s.b_len)].map(|(start, len)| Span { start, len });
            let terms = self.terms[s.terms.range()].iter().map(|t| t.set);
            let mut reads = operands.into_iter().chain(terms);
            assert!(
                inside(k) && reads.all(|r| inside(r) && apart(r, k)),
                "forward sweep plan: a set outside the store or read while written"
            );
        }
        assert!(self.seeds.iter().all(|&i| i < self.len));
        assert!(self.outputs.iter().all(|&o| inside(o)));
    }
}

/// One term `c · j` of a collapsed linear combination: a stored node `j` reached from the
/// combination's root through operations with constant partials whose intermediate
/// results are used nowhere else (and store nothing).
#[derive(Clone, Copy, Debug)]
struct Term {
    /// `j`'s set in the store of the sweep: `P(j)` (forward), `R(j)` (reverse).
    set: Span,
    /// Forward `P(j) → P(root)`; reverse `R(root) → R(j)`.
    map: Map,
    /// The coefficient of `j` in the combination.
    w: Weight,
}

/// The coefficient of one node in a collapsed combination: the product of the constant
/// partials along the path from the root, times, through a folded operation, that
/// operation's local partial at the evaluation point.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Weight {
    /// Product of the constant partials along the path.
    coef: f64,
    /// The folded operation whose local partial also multiplies `coef`.
    part: u32,
    /// Which partial: 0 none, 1 `∂/∂a`, 2 `∂/∂b`, 3 their sum (both operands the node).
    side: u8,
}

/// The partial `side` (1 `∂/∂a`, 2 `∂/∂b`, otherwise their sum) of the operation partials
/// `[∂/∂a, ∂/∂b]`.
#[inline(always)]
fn partial_of(side: u8, [pa, pb]: [f64; 2]) -> f64 {
    match side {
        1 => pa,
        2 => pb,
        _ => pa + pb,
    }
}

/// One stored node of a collapsed combination and its coefficient.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Leaf {
    node: u32,
    w: Weight,
}

/// A slice `[start, start + len)` of one of the stores.
#[derive(Clone, Copy, Debug, Default)]
struct Span {
    start: u32,
    len: u32,
}

impl Span {
    #[inline]
    fn range(self) -> std::ops::Range<usize> {
        self.start as usize..(self.start + self.len) as usize
    }
}

/// One active operation of the second-order adjoint sweep (reverse order), with the spans
/// of its index sets and its maps together.
#[derive(Clone, Copy, Debug)]
struct RevStep {
    /// Operation index (row of the local partials) and node index.
    t: u32,
    k: u32,
    /// `R(k)`, `R(a)`, `R(b)` in the adjoint store (length 0: no such operand).
    rk: Span,
    ra: Span,
    rb: Span,
    /// `P(a)`, `P(b)` in the gradient store.
    pa: Span,
    pb: Span,
    maps: OpMaps,
    curv: Curvature,
    /// Both operands are the same node.
    same: bool,
    /// A collapsed linear combination (non-empty): `ȧ` of each term's node gets
    /// `coef · ȧₖ`, through these terms of `SparsePlan::rterms`, instead of the operands.
    terms: Span,
}

/// The static index sets and maps of the sparse sweeps of one tape.
#[derive(Clone, Debug, Default)]
pub(super) struct SparsePlan {
    /// Length of the second-order adjoint store, and of its leading part held by the
    /// inputs (the Hessian rows). The inputs' sets `R(i)` come first, one after another;
    /// the others share places by liveness (a set is placed at the first step of the
    /// reverse sweep that adds to it and freed after its own step), so the store is the
    /// peak live size, not the sum of all sets.
    adot_len: u32,
    adot_inputs: u32,
    /// The second-order adjoint sweep, active operations in descending order.
    rev: Vec<RevStep>,
    /// Terms of the collapsed linear combinations of `rev`.
    rterms: Vec<Term>,
    /// The forward gradient sweep that keeps every set at its own place (node order), for
    /// the second-order sweep that reads them afterwards.
    full: FwdPlan,
    /// The same sweep with places reused by liveness (a set lives from its own step to
    /// its last reader; the outputs' to the end), for Jacobians alone: a store of the
    /// most entries live at once, small enough to stay in cache.
    compact: FwdPlan,
    store: Vec<u32>,
    /// `(position in ȧ store, Hessian entry)` for the lower triangle, in pattern order.
    hes_extract: Vec<u32>,
}

fn flat(sets: &BitSets, n: usize) -> (Vec<u32>, Vec<u32>) {
    let mut off = Vec::with_capacity(n + 1);
    let mut idx = Vec::new();
    off.push(0);
    for k in 0..n {
        idx.extend(bits(sets.row(k)).map(|i| i as u32));
        off.push(idx.len() as u32);
    }
    (off, idx)
}

/// Store offsets of the sets with offsets `full` when collapsed nodes store nothing.
fn stored_offsets(full: &[u32], collapsed: &[bool]) -> Vec<u32> {
    let mut off = Vec::with_capacity(full.len());
    off.push(0u32);
    for (k, &c) in collapsed.iter().enumerate() {
        let len = if c { 0 } else { full[k + 1] - full[k] };
        off.push(off[k] + len);
    }
    off
}

fn slice<'a>(off: &[u32], idx: &'a [u32], k: usize) -> &'a [u32] {
    if k + 1 >= off.len() {
        &[]
    } else {
        &idx[off[k] as usize..off[k + 1] as usize]
    }
}

fn map_of(src: &[u32], dst: &[u32], store: &mut Vec<u32>) -> Map {
    if src == dst {
        return Map {
            off: 0,
            ident: true,
        };
    }
    let off = store.len() as u32;
    let mut p = 0;
    for &s in src {
        while dst[p] != s {
            p += 1;
        }
        store.push(p as u32);
    }
    Map { off, ident: false }
}

impl SparsePlan {
    /// Builds the sets `P`, `R` and all maps; returns the plan and the lower-triangle
    /// Hessian pattern it produces.
    pub(super) fn new(
        n_in: usize,
        ops: &[Op],
        args: &[[u32; 2]],
        active: &[bool],
        outputs: &[u32],
        jset: &BitSets,
    ) -> (SparsePlan, Pattern) {
        let n = n_in + ops.len();
        let (pfull, pidx) = flat(jset, n);
        let p = |k: u32| slice(&pfull, &pidx, k as usize);
        let (collapsed, fcollapsed) = collapsible(n_in, ops, args, active, outputs);
        let poff = stored_offsets(&pfull, &fcollapsed);
        // R sets, reverse order; the sink (index n) has empty P and R.
        let mut r = BitSets::new(n + 1, n_in);
        let sink = n as u32;
        let empty = vec![0u64; jset.words()];
        let prow = |k: usize| if k < n { jset.row(k) } else { &empty[..] };
        let curv: Vec<Curvature> = ops.iter().map(|o| o.curvature()).collect();
        for t in (0..ops.len()).rev() {
            let k = n_in + t;
            if !active[k] {
                continue;
            }
            let [a, b] = args[t];
            let (a, b) = (a as usize, b as usize);
            r.union_rows(a, k);
            if b != a {
                r.union_rows(b, k);
            }
            match curv[t] {
                Curvature::Linear => {}
                _ if a == b => r.union_with(a, prow(a)),
                Curvature::Unary => r.union_with(a, prow(a)),
                Curvature::Bilinear | Curvature::Quotient => {
                    r.union_with(a, prow(b));
                    r.union_with(b, prow(a));
                    if curv[t] == Curvature::Quotient {
                        r.union_with(b, prow(b));
                    }
                }
            }
        }
        // The sink collects nothing meaningful.
        let (rfull, ridx) = flat(&r, n);
        let rs = |k: u32| slice(&rfull, &ridx, k as usize);
        let mut store = Vec::new();
        let mut maps = Vec::with_capacity(ops.len());
        for t in 0..ops.len() {
            let k = (n_in + t) as u32;
            let mut m = OpMaps::default();
            if active[k as usize] && !collapsed[k as usize] {
                let [a, b] = args[t];
                let stored = !fcollapsed[k as usize];
                if a != sink {
                    if stored {
                        m.fa = map_of(p(a), p(k), &mut store);
                    }
                    m.ra = map_of(rs(k), rs(a), &mut store);
                    m.pa_ra = map_opt(p(a), rs(a), &mut store);
                    m.pb_ra = map_opt(p(b), rs(a), &mut store);
                }
                if b != sink && b != a {
                    if stored {
                        m.fb = map_of(p(b), p(k), &mut store);
                    }
                    m.rb = map_of(rs(k), rs(b), &mut store);
                    m.pa_rb = map_opt(p(a), rs(b), &mut store);
                    m.pb_rb = map_opt(p(b), rs(b), &mut store);
                }
            }
            maps.push(m);
        }
        // Places of the R sets: the inputs' first (the Hessian rows, read at the end); the
        // others are placed while the reverse sweep is planned below.
        let mut rplaces = Places::new(n, |k| {
            if collapsed[k] {
                0
            } else {
                rfull[k + 1] - rfull[k]
            }
        });
        for i in 0..n_in {
            rplaces.place(i as u32);
        }
        let adot_inputs = rplaces.slots.peak();
        let mut pattern = Pattern {
            n_rows: n_in,
            n_cols: n_in,
            ..Pattern::default()
        };
        let mut hes_extract = Vec::new();
        for i in 0..n_in {
            let row = rs(i as u32);
            for (pos, &j) in row.iter().enumerate() {
                if j as usize <= i {
                    pattern.rows.push(i as u32);
                    pattern.cols.push(j);
                    hes_extract.push(rplaces.place(i as u32).start + pos as u32);
                }
            }
        }
        // `P(k)` in the full forward store (empty for the sink).
        let pspan = |k: u32| {
            if k == sink {
                Span::default()
            } else {
                let (start, end) = (poff[k as usize], poff[k as usize + 1]);
                Span {
                    start,
                    len: end - start,
                }
            }
        };
        // Collapsed combinations per root, leaves merged in ascending node order: `rcombos`
        // through linear nodes only (reverse sweep), `fcombos` also through folded
        // products (forward sweep).
        let combinations = |fold: &[bool]| {
            let mut combos: Vec<Option<Vec<Leaf>>> = vec![None; ops.len()];
            let mut leaves = Vec::new();
            for t in (0..ops.len()).filter(|&t| active[n_in + t] && !fold[n_in + t]) {
                let [a, b] = args[t];
                let folds = |j: u32| j != sink && fold[j as usize];
                if folds(a) || folds(b) {
                    leaves.clear();
                    let root = (n_in + t) as u32;
                    let cx = LeafContext {
                        n_in,
                        ops,
                        args,
                        folded: fold,
                        sink,
                    };
                    combination_leaves(&cx, root, 1.0, &mut leaves);
                    combos[t] = Some(merge_leaves(&mut leaves));
                }
            }
            combos
        };
        let rcombos = combinations(&collapsed);
        let fcombos = combinations(&fcollapsed);
        // Each R set is placed at the first step that adds to it (an operand, or a leaf of a
        // collapsed combination) and freed after its own step has read and zeroed it.
        let mut rterms = Vec::new();
        let mut rev = Vec::new();
        for t in (0..ops.len())
            .rev()
            .filter(|&t| active[n_in + t] && !collapsed[n_in + t])
        {
            let [a, b] = args[t];
            let k = (n_in + t) as u32;
            let mut step = RevStep {
                t: t as u32,
                k,
                rk: rplaces.place(k),
                ra: rplaces.place(a),
                rb: if b == a {
                    Span::default()
                } else {
                    rplaces.place(b)
                },
                pa: pspan(a),
                pb: pspan(b),
                maps: maps[t],
                curv: curv[t],
                same: a == b,
                terms: Span::default(),
            };
            if let Some(combo) = &rcombos[t] {
                step.terms = push_terms(&mut rterms, combo, |j| {
                    (rplaces.place(j), map_of(rs(k), rs(j), &mut store))
                });
            }
            rev.push(step);
            rplaces.free(k);
        }
        let fwd_ops: Vec<usize> = (0..ops.len())
            .filter(|&t| active[n_in + t] && !fcollapsed[n_in + t])
            .collect();
        // Nodes whose stored gradients a forward step reads: its combination's leaves, or
        // its operands.
        let reads = |t: usize| -> Vec<u32> {
            match &fcombos[t] {
                Some(combo) => {
                    // A node can be a leaf twice (through different folded partials).
                    let mut r: Vec<u32> = combo.iter().map(|l| l.node).collect();
                    r.dedup();
                    r
                }
                None => {
                    let [a, b] = args[t];
                    let mut r = vec![a];
                    if b != a {
                        r.push(b);
                    }
                    r.retain(|&j| j != sink);
                    r
                }
            }
        };
        let mut full = FwdPlan {
            len: *poff.last().unwrap_or(&0),
            ..FwdPlan::default()
        };
        let mut compact = FwdPlan::default();
        let mut last_read = vec![usize::MAX; n];
        for (i, &t) in fwd_ops.iter().enumerate() {
            for j in reads(t) {
                last_read[j as usize] = i;
            }
        }
        let mut is_output = vec![false; n];
        for &o in outputs {
            is_output[o as usize] = true;
        }
        let mut places = Places::new(n, |k| pspan(k as u32).len);
        for i in 0..n_in as u32 {
            let s = pspan(i);
            if s.len > 0 {
                full.seeds.push(s.start);
                compact.seeds.push(places.place(i).start);
            }
        }
        for (i, &t) in fwd_ops.iter().enumerate() {
            let [a, b] = args[t];
            let k = (n_in + t) as u32;
            let b = if b == a { sink } else { b };
            // Placed while its operands are still live, so never on top of them.
            places.place(k);
            let step = |span: &mut dyn FnMut(u32) -> Span| {
                let (ks, as_, bs) = (span(k), span(a), span(b));
                FwdStep {
                    t: t as u32,
                    k: ks.start,
                    k_len: ks.len,
                    a: as_.start,
                    a_len: as_.len,
                    b: bs.start,
                    b_len: bs.len,
                    fa: maps[t].fa,
                    fb: maps[t].fb,
                    same: a == args[t][1],
                    terms: Span::default(),
                }
            };
            let mut fs = step(&mut |j| pspan(j));
            let mut cs = step(&mut |j| places.place(j));
            if let Some(combo) = &fcombos[t] {
                let mut tmaps = Vec::with_capacity(combo.len());
                fs.terms = push_terms(&mut full.terms, combo, |j| {
                    let m = map_of(p(j), p(k), &mut store);
                    tmaps.push(m);
                    (pspan(j), m)
                });
                let mut tm = tmaps.into_iter();
                cs.terms = push_terms(&mut compact.terms, combo, |j| {
                    (places.place(j), tm.next().expect("one map per leaf"))
                });
            }
            full.steps.push(fs);
            compact.steps.push(cs);
            for j in reads(t) {
                if last_read[j as usize] == i && !is_output[j as usize] {
                    places.free(j);
                }
            }
            if last_read[k as usize] == usize::MAX && !is_output[k as usize] {
                places.free(k);
            }
        }
        for &o in outputs {
            full.outputs.push(pspan(o));
            compact.outputs.push(places.place(o));
        }
        compact.len = places.slots.peak();
        place_kept_partials(&mut compact, ops.len());
        full.check_places();
        compact.check_places();
        (
            SparsePlan {
                adot_len: rplaces.slots.peak(),
                adot_inputs,
                rev,
                rterms,
                full,
                compact,
                store,
                hes_extract,
            },
            pattern,
        )
    }

    /// Length of the forward gradient store.
    pub(super) fn grad_len(&self) -> usize {
        self.full.len as usize
    }
    /// Length of the forward gradient store of the Jacobian-only sweep (places reused by
    /// liveness).
    pub(super) fn jacobian_grad_len(&self) -> usize {
        self.compact.len as usize
    }
    /// Length of the second-order adjoint store.
    pub(super) fn adot_len(&self) -> usize {
        self.adot_len as usize
    }
    /// The forward sweep that keeps every gradient set (before a second-order sweep).
    pub(super) fn full(&self) -> &FwdPlan {
        &self.full
    }
    /// The forward sweep with places reused by liveness (Jacobians alone).
    pub(super) fn compact(&self) -> &FwdPlan {
        &self.compact
    }
    /// Length of the store of kept partials of the Jacobian's fused sweep.
    pub(super) fn kept_len(&self) -> usize {
        self.compact.saved_len as usize
    }
    /// Total number of stored map positions (memory report).
    pub(super) fn map_len(&self) -> usize {
        self.store.len()
    }
}

/// Places of per-node index sets in a store ([`Slots`]) shared by liveness, given out in
/// the order a sweep first touches them: the second-order adjoint sets `R(k)` of the
/// reverse sweep, the gradient sets `P(k)` of the Jacobian-only forward sweep.
struct Places<F> {
    slots: Slots,
    span: Vec<Option<Span>>,
    /// Stored length of node `k`'s set (0 for collapsed nodes).
    len: F,
}

impl<F: Fn(usize) -> u32> Places<F> {
    fn new(n: usize, len: F) -> Self {
        Places {
            slots: Slots::default(),
            span: vec![None; n],
            len,
        }
    }

    /// The place of node `k`'s set, given out on the first call (empty for the sink).
    fn place(&mut self, k: u32) -> Span {
        let Some(entry) = self.span.get_mut(k as usize) else {
            return Span::default();
        };
        *entry.get_or_insert_with(|| {
            let len = (self.len)(k as usize);
            Span {
                start: self.slots.alloc(len),
                len,
            }
        })
    }

    /// Gives the place of node `k`'s set back (after its last use).
    fn free(&mut self, k: u32) {
        if let Some(Some(s)) = self.span.get(k as usize) {
            self.slots.free(s.start, s.len);
        }
    }
}

/// Gives each folded operation whose partials a term of `plan` reads a place in the store
/// of kept partials, from the operation to the step that reads them (places reused by
/// liveness, so the store is a handful of entries), and makes the terms name that place.
fn place_kept_partials(plan: &mut FwdPlan, n_ops: usize) {
    let mut reader = vec![usize::MAX; n_ops];
    for (i, s) in plan.steps.iter().enumerate() {
        for term in plan.terms[s.terms.range()].iter().filter(|t| t.w.side != 0) {
            reader[term.w.part as usize] = i;
        }
    }
    let mut slots = Slots::default();
    let mut save = vec![u32::MAX; n_ops];
    let mut next = 0;
    for t in 0..n_ops {
        if reader[t] != usize::MAX {
            save[t] = slots.alloc(1);
        }
        let Some(s) = plan.steps.get(next) else {
            continue;
        };
        if s.t as usize != t {
            continue;
        }
        for term in &plan.terms[s.terms.range()] {
            let op = term.w.part as usize;
            if term.w.side != 0 && reader[op] == next {
                slots.free(save[op], 1);
                reader[op] = usize::MAX;
            }
        }
        next += 1;
    }
    for term in plan.terms.iter_mut().filter(|t| t.w.side != 0) {
        term.w.part = save[term.w.part as usize];
    }
    plan.saved_len = slots.peak();
    plan.save = save;
}

/// Appends one term per leaf of `combo`, with the node's set and map from `set_map`;
/// returns their span in `terms`.
fn push_terms(
    terms: &mut Vec<Term>,
    combo: &[Leaf],
    mut set_map: impl FnMut(u32) -> (Span, Map),
) -> Span {
    let start = terms.len() as u32;
    for leaf in combo {
        let (set, map) = set_map(leaf.node);
        terms.push(Term {
            set,
            map,
            w: leaf.w,
        });
    }
    Span {
        start,
        len: terms.len() as u32 - start,
    }
}

/// The nodes whose gradients need not be stored, as two masks `(linear, folded)`.
///
/// `linear`: results of operations with constant partials used by exactly one operation,
/// itself with constant partials, and not an output; their contributions are summed
/// directly into the gradient of the first node down the chain that is stored (the root
/// of the linear combination), in both sweeps. `folded` adds, for the forward sweep only,
/// the results of operations with variable partials used once, by an operation with
/// constant partials, and not an output (their operands are then always stored, since
/// their only user has variable partials).
fn collapsible(
    n_in: usize,
    ops: &[Op],
    args: &[[u32; 2]],
    active: &[bool],
    outputs: &[u32],
) -> (Vec<bool>, Vec<bool>) {
    let n = n_in + ops.len();
    let mut uses = vec![0u32; n];
    let mut user = vec![u32::MAX; n];
    for (t, [a, b]) in args.iter().enumerate() {
        if !active[n_in + t] {
            continue;
        }
        for j in [*a, *b].into_iter().take(if a == b { 1 } else { 2 }) {
            if (j as usize) < n {
                uses[j as usize] += 1;
                user[j as usize] = t as u32;
            }
        }
    }
    for &o in outputs {
        uses[o as usize] += 2;
    }
    let single_linear_use = |k: usize| {
        k >= n_in
            && active[k]
            && uses[k] == 1
            && ops[user[k] as usize].constant_partials().is_some()
    };
    let linear: Vec<bool> = (0..n)
        .map(|k| single_linear_use(k) && ops[k - n_in].constant_partials().is_some())
        .collect();
    let folded = (0..n)
        .map(|k| linear[k] || (single_linear_use(k) && args[k - n_in] != [n as u32; 2]))
        .collect();
    (linear, folded)
}

/// What the leaf search of a collapsed combination reads.
struct LeafContext<'a> {
    n_in: usize,
    ops: &'a [Op],
    args: &'a [[u32; 2]],
    /// Nodes collapsed in the sweep being planned (`collapsed`, or it plus folded ones).
    folded: &'a [bool],
    sink: u32,
}

/// Appends the stored leaves of the combination reached through node `k` (a collapsed
/// node or the root), `scale` the product of constant partials from the root to `k`.
fn combination_leaves(cx: &LeafContext<'_>, k: u32, scale: f64, out: &mut Vec<Leaf>) {
    let t = k as usize - cx.n_in;
    let [a, b] = cx.args[t];
    let partials = cx.ops[t].constant_partials();
    // Same operand twice (`x * x`, `x - x`, unary ops): one operand, partials summed.
    let operands = if a == b {
        [(a, 3u8), (cx.sink, 0)]
    } else {
        [(a, 1), (b, 2)]
    };
    for (j, side) in operands {
        if j == cx.sink {
            continue;
        }
        match partials {
            Some(p) => {
                let c = scale * partial_of(side, p);
                if cx.folded[j as usize] {
                    combination_leaves(cx, j, c, out);
                } else {
                    let w = Weight {
                        coef: c,
                        part: 0,
                        side: 0,
                    };
                    out.push(Leaf { node: j, w });
                }
            }
            // A folded operation: its operands are stored; its partial is read at
            // evaluation time.
            None => {
                let w = Weight {
                    coef: scale,
                    part: t as u32,
                    side,
                };
                out.push(Leaf { node: j, w });
            }
        }
    }
}

/// Sorts leaves by node and merges those with the same node and the same folded partial.
fn merge_leaves(leaves: &mut [Leaf]) -> Vec<Leaf> {
    let key = |l: &Leaf| (l.node, l.w.part, l.w.side);
    leaves.sort_by_key(key);
    let mut merged: Vec<Leaf> = Vec::with_capacity(leaves.len());
    for &l in leaves.iter() {
        match merged.last_mut() {
            Some(m) if key(m) == key(&l) => m.w.coef += l.w.coef,
            _ => merged.push(l),
        }
    }
    merged
}

/// A map only when both sets are non-empty and the source is a subset of the target.
fn map_opt(src: &[u32], dst: &[u32], store: &mut Vec<u32>) -> Map {
    if src.is_empty() || src.iter().any(|s| dst.binary_search(s).is_err()) {
        Map::default()
    } else {
        map_of(src, dst, store)
    }
}

/// `dst[map[i]][l] += c[l] * src[i][l]` for every lane `l` (or `dst[i]` for the identity).
#[inline(always)]
fn axpy<const L: usize>(
    dst: &mut [[f64; L]],
    src: &[[f64; L]],
    c: [f64; L],
    m: Map,
    store: &[u32],
) {
    if m.ident {
        for (d, s) in dst.iter_mut().zip(src) {
            for l in 0..L {
                d[l] += c[l] * s[l];
            }
        }
    } else {
        let pos = &store[m.off as usize..m.off as usize + src.len()];
        for (&p, s) in pos.iter().zip(src) {
            // SAFETY: every stored position was found inside the destination set when the
            // plan was built (`map_of` indexes that set with bounds checks), and every
            // caller passes that set's slice of the store as `dst`.
            let d = unsafe { dst.get_unchecked_mut(p as usize) };
            for l in 0..L {
                d[l] += c[l] * s[l];
            }
        }
    }
}

/// Checks that `g` holds the store of `plan` and writes the inputs' unit seeds.
#[inline(always)]
fn seed_gradients<const L: usize>(plan: &FwdPlan, g: &mut [[f64; L]]) {
    assert!(
        g.len() >= plan.len as usize,
        "gradient store shorter than the plan"
    );
    for &i in &plan.seeds {
        g[i as usize] = [1.0; L];
    }
}

/// One step of a forward sparse gradient sweep: `P(k)` of step `s` from its operands'
/// sets with the operation's partials `p`, or from its combination's `terms`, whose folded
/// partials are `term_part[w.part]`.
///
/// # Safety
/// `base` is the start of a gradient store at least as long as the plan of `s` and
/// `terms`, not otherwise accessed during the call.
#[inline(always)]
unsafe fn forward_step<const L: usize>(
    s: &FwdStep,
    p: [[f64; L]; 2],
    terms: &[Term],
    term_part: &[[[f64; L]; 2]],
    store: &[u32],
    base: *mut [f64; L],
) {
    // SAFETY: every span of the plan lies within its `len` entries (checked when the plan
    // was built; the caller passes a store at least that long), and the result's set is
    // disjoint from every set its step reads (operands precede it, or were placed before
    // it and are still live), so the one mutable and the shared slices never overlap.
    let gk = unsafe { std::slice::from_raw_parts_mut(base.add(s.k as usize), s.k_len as usize) };
    let read = |start: u32, len: u32| -> &[[f64; L]] {
        // SAFETY: as above.
        unsafe { std::slice::from_raw_parts(base.add(start as usize), len as usize) }
    };
    if s.terms.len > 0 {
        let coefficient = |w: Weight| {
            let mut c = [w.coef; L];
            if w.side != 0 {
                let [pa, pb] = term_part[w.part as usize];
                for l in 0..L {
                    c[l] *= partial_of(w.side, [pa[l], pb[l]]);
                }
            }
            c
        };
        for (i, term) in terms[s.terms.range()].iter().enumerate() {
            let (c, x) = (coefficient(term.w), read(term.set.start, term.set.len));
            if i == 0 {
                first_term(gk, x, c, term.map, store);
            } else {
                axpy(gk, x, c, term.map, store);
            }
        }
        return;
    }
    let [mut ca, cb] = p;
    if s.same {
        for l in 0..L {
            ca[l] += cb[l];
        }
    }
    if s.a_len > 0 {
        first_term(gk, read(s.a, s.a_len), ca, s.fa, store);
    } else {
        gk.iter_mut().for_each(|x| *x = [0.0; L]);
    }
    if s.b_len > 0 {
        axpy(gk, read(s.b, s.b_len), cb, s.fb, store);
    }
}

/// `dst = c · src` through the map `m`: written directly when `src` is on `dst`'s own
/// index set, else `dst` zeroed and `c · src` scattered into it ([`axpy`]).
#[inline(always)]
fn first_term<const L: usize>(
    dst: &mut [[f64; L]],
    src: &[[f64; L]],
    c: [f64; L],
    m: Map,
    store: &[u32],
) {
    if m.ident {
        for (d, x) in dst.iter_mut().zip(src) {
            for l in 0..L {
                d[l] = c[l] * x[l];
            }
        }
    } else {
        dst.iter_mut().for_each(|x| *x = [0.0; L]);
        axpy(dst, src, c, m, store);
    }
}

/// `d[src]` to read and `d[dst]` to write: two sets live at the same step of the reverse
/// sweep, which [`Slots`] placed apart.
#[inline(always)]
fn read_write<T>(d: &mut [T], src: Span, dst: Span) -> (&[T], &mut [T]) {
    if dst.start >= src.start + src.len {
        let (lo, hi) = d.split_at_mut(dst.start as usize);
        (&lo[src.range()], &mut hi[..dst.len as usize])
    } else {
        let (lo, hi) = d.split_at_mut(src.start as usize);
        (&hi[..src.len as usize], &mut lo[dst.range()])
    }
}

impl super::Tape {
    /// Forward sparse gradients of every stored node into `g` by the sweep `plan` (the
    /// tape's [`SparsePlan::full`]), for `L` evaluation points at once (lane `l` uses lane
    /// `l` of the partials `part` of the `forward::<1>` sweep).
    #[inline(always)]
    pub(super) fn sparse_forward<const L: usize>(
        &self,
        plan: &FwdPlan,
        part: &[[[f64; L]; 2]],
        g: &mut [[f64; L]],
    ) {
        seed_gradients(plan, g);
        let base = g.as_mut_ptr();
        for s in &plan.steps {
            // SAFETY: `g` holds the plan's store (checked by `seed_gradients`), `base` is its
            // start and `g` is not used otherwise during the loop.
            unsafe {
                forward_step(
                    s,
                    part[s.t as usize],
                    &plan.terms,
                    part,
                    &self.sparse.store,
                    base,
                )
            };
        }
    }

    /// Values and forward sparse gradients (the Jacobian's sweep [`SparsePlan::compact`]) in
    /// one pass over the operations at `L` points: each operation's partials go from its
    /// evaluation straight into its gradient step, and only those a later combination
    /// reads (folded operations') are kept, in `kept`. Values into their places
    /// ([`super::registers::Registers`]) in `vals`, gradients into `g`; same numbers as
    /// [`Tape::forward`] followed by [`Tape::sparse_forward`].
    #[inline(always)]
    pub(super) fn value_gradient_sweep<const L: usize>(
        &self,
        xs: [&[f64]; L],
        vals: &mut [[f64; L]],
        kept: &mut [[[f64; L]; 2]],
        g: &mut [[f64; L]],
    ) {
        let plan = &self.sparse.compact;
        let regs = &self.registers;
        let vals = &mut vals[..regs.len as usize];
        assert!(
            kept.len() >= plan.saved_len as usize,
            "kept-partial store shorter than the plan"
        );
        seed_gradients(plan, g);
        self.seed_inputs(xs, vals);
        let base = g.as_mut_ptr();
        let mut steps = plan.steps.iter().peekable();
        for (t, (op, &dst)) in regs.ops.iter().zip(&regs.dst).enumerate() {
            let local = self.local::<1, L>(*op, vals, xs);
            vals[dst as usize] = local.val;
            let keep = plan.save[t];
            if keep != u32::MAX {
                kept[keep as usize] = local.part;
            }
            if let Some(s) = steps.next_if(|s| s.t as usize == t) {
                // SAFETY: as in `sparse_forward`.
                unsafe { forward_step(s, local.part, &plan.terms, kept, &self.sparse.store, base) };
            }
        }
    }

    /// Copies the Jacobian rows (forward sparse gradients of the outputs, left in `g` by
    /// the sweep `plan`) of the first lanes into `jacs`, one block of the pattern's values
    /// per lane (as many lanes as `jacs` holds blocks, at most `L`), in one pass over `g`.
    pub(super) fn sparse_jacobian_extract<const L: usize>(
        &self,
        plan: &FwdPlan,
        g: &[[f64; L]],
        jacs: &mut [f64],
    ) {
        let nnz = self.jac_pattern.nnz();
        if nnz == 0 {
            return;
        }
        let points = (jacs.len() / nnz).min(L);
        let mut blocks = jacs.chunks_exact_mut(nnz);
        let mut lanes: [&mut [f64]; L] = std::array::from_fn(|_| blocks.next().unwrap_or_default());
        let mut e = 0;
        for o in &plan.outputs {
            for v in &g[o.range()] {
                for (l, jac) in lanes[..points].iter_mut().enumerate() {
                    jac[e] = v[l];
                }
                e += 1;
            }
        }
    }

    /// Second-order adjoint sweep for `L` evaluation points at once, and extraction of the
    /// Hessian lower triangle of each lane into `hes[l]` (needs `forward::<2>` and
    /// `adjoint_sweep` per lane, and `sparse_forward` into `g`). `d` is left zeroed.
    #[inline(always)]
    pub(super) fn sparse_hessian<const L: usize>(
        &self,
        loc: &super::Locals<L>,
        g: &[[f64; L]],
        d: &mut [[f64; L]],
        hes: [&mut [f64]; L],
    ) {
        let sp = &self.sparse;
        for s in &sp.rev {
            if s.terms.len > 0 {
                // Linear: no curvature terms, only ȧⱼ += c ȧₖ for each term.
                for term in &sp.rterms[s.terms.range()] {
                    let (dk, dj) = read_write(d, s.rk, term.set);
                    axpy(dj, dk, [term.w.coef; L], term.map, &sp.store);
                }
                d[s.rk.range()].iter_mut().for_each(|x| *x = [0.0; L]);
                continue;
            }
            let t = s.t as usize;
            let (mut pa, mut pb, mut cs, mut cab, mut cbb) =
                ([0.0; L], [0.0; L], [0.0; L], [0.0; L], [0.0; L]);
            let [part_a, part_b] = loc.part[t];
            let [sec_aa, sec_ab, sec_bb] = loc.sec[t];
            let abar_k = loc.abar[s.k as usize];
            for l in 0..L {
                let (a, b) = (part_a[l], part_b[l]);
                let (saa, sab, sbb) = (sec_aa[l], sec_ab[l], sec_bb[l]);
                let ak = abar_k[l];
                if s.same {
                    pa[l] = a + b;
                    cs[l] = ak * (saa + 2.0 * sab + sbb);
                } else {
                    (pa[l], pb[l]) = (a, b);
                    cab[l] = ak * sab;
                    cbb[l] = ak * sbb;
                }
            }
            let m = &s.maps;
            let nonlinear = s.curv != Curvature::Linear;
            let ga = &g[s.pa.range()];
            let gb = &g[s.pb.range()];
            if s.same {
                let (dk, da) = read_write(d, s.rk, s.ra);
                axpy(da, dk, pa, m.ra, &sp.store);
                if nonlinear {
                    axpy(da, ga, cs, m.pa_ra, &sp.store);
                }
            } else {
                if s.ra.len > 0 {
                    let (dk, da) = read_write(d, s.rk, s.ra);
                    axpy(da, dk, pa, m.ra, &sp.store);
                    if nonlinear && !gb.is_empty() {
                        axpy(da, gb, cab, m.pb_ra, &sp.store);
                    }
                }
                if s.rb.len > 0 {
                    let (dk, db) = read_write(d, s.rk, s.rb);
                    axpy(db, dk, pb, m.rb, &sp.store);
                    if nonlinear {
                        if !ga.is_empty() {
                            axpy(db, ga, cab, m.pa_rb, &sp.store);
                        }
                        if s.curv == Curvature::Quotient && !gb.is_empty() {
                            axpy(db, gb, cbb, m.pb_rb, &sp.store);
                        }
                    }
                }
            }
            d[s.rk.range()].iter_mut().for_each(|x| *x = [0.0; L]);
        }
        for (l, h) in hes.into_iter().enumerate() {
            for (h, &pos) in h.iter_mut().zip(&sp.hes_extract) {
                *h = d[pos as usize][l];
            }
        }
        d[..sp.adot_inputs as usize]
            .iter_mut()
            .for_each(|x| *x = [0.0; L]);
    }
}

impl super::Tape {
    /// [`super::Tape::sparse_forward`] for a batch of `L` lanes, with wide vectors when
    /// the processor has them ([`with_wide_vectors`]).
    pub(super) fn sparse_forward_batch<const L: usize>(
        &self,
        plan: &FwdPlan,
        part: &[[[f64; L]; 2]],
        g: &mut [[f64; L]],
    ) {
        with_wide_vectors(
            #[inline(always)]
            || self.sparse_forward(plan, part, g),
        )
    }

    /// [`super::Tape::value_gradient_sweep`] for a batch of `L` lanes, with wide vectors
    /// when the processor has them ([`with_wide_vectors`]).
    pub(super) fn value_gradient_batch<const L: usize>(
        &self,
        xs: [&[f64]; L],
        vals: &mut [[f64; L]],
        kept: &mut [[[f64; L]; 2]],
        g: &mut [[f64; L]],
    ) {
        with_wide_vectors(
            #[inline(always)]
            || self.value_gradient_sweep(xs, vals, kept, g),
        )
    }

    /// [`super::Tape::sparse_hessian`] for a batch of `L` lanes, with wide vectors when
    /// the processor has them ([`with_wide_vectors`]).
    pub(super) fn sparse_hessian_batch<const L: usize>(
        &self,
        loc: &super::Locals<L>,
        g: &[[f64; L]],
        d: &mut [[f64; L]],
        hes: [&mut [f64]; L],
    ) {
        with_wide_vectors(
            #[inline(always)]
            || self.sparse_hessian(loc, g, d, hes),
        )
    }
}

/// Runs `f` compiled a second time for 256-bit vectors (AVX2) when the processor has them
/// (chosen at run time; a batch entry of 8 `f64` lanes is two AVX2 operations where the
/// baseline x86-64 build needs four SSE2 ones), else as built. Same operations in
/// the same order, no fused multiply-add: the numbers are identical. `f` inlines the
/// `#[inline(always)]` sweeps, so they are compiled inside the AVX2 function.
#[inline(always)]
pub(super) fn with_wide_vectors<R>(f: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        #[target_feature(enable = "avx2")]
        unsafe fn avx2<R>(f: impl FnOnce() -> R) -> R {
            f()
        }
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { avx2(f) };
    }
    f()
}
