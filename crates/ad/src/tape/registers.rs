//! Places of the node values in a short store for the forward sweeps, which need each value
//! only until its last reader (the reverse sweeps read partials and adjoints, not values):
//! a value lives from its operation to the last operation that reads it (inputs and
//! outputs for the whole sweep), and places are reused by liveness, so the store holds the most values live at once instead of every
//! node — a few hundred kilobytes for a batch of points instead of megabytes, which stay
//! in cache while the sweep writes and reads them.

use super::op::Op;
use super::slots::Slots;

/// The operations with operands renamed to value places, and where results go.
#[derive(Clone, Debug, Default)]
pub(super) struct Registers {
    /// The tape's operations with operand node indices replaced by their places.
    pub ops: Vec<Op>,
    /// Place of each operation's result.
    pub dst: Vec<u32>,
    /// Place of each output's value, in output order.
    pub outputs: Vec<u32>,
    /// Length of the store (the inputs' places `0..n_in` first).
    pub len: u32,
}

impl Registers {
    /// Places for the values of a tape with `n_in` inputs (nodes `0..n_in`, kept for the
    /// whole sweep), operations `ops` (node `n_in + t`) and output nodes `outputs`.
    pub(super) fn new(n_in: usize, ops: &[Op], outputs: &[u32]) -> Self {
        let n = n_in + ops.len();
        let mut last_read = vec![usize::MAX; n];
        let mut args = Vec::new();
        for (t, op) in ops.iter().enumerate() {
            op.value_args(&mut args);
            for &j in &args {
                last_read[j as usize] = t;
            }
        }
        let mut kept = vec![false; n];
        kept[..n_in].iter_mut().for_each(|k| *k = true);
        for &o in outputs {
            kept[o as usize] = true;
        }
        let mut slots = Slots::default();
        let mut place: Vec<u32> = (0..n_in).map(|_| slots.alloc(1)).collect();
        place.resize(n, u32::MAX);
        let mut renamed = Vec::with_capacity(ops.len());
        let mut dst = Vec::with_capacity(ops.len());
        for (t, op) in ops.iter().enumerate() {
            renamed.push(op.remap(&place));
            // The result's place is taken before the operands' are given back, so an
            // operation never writes where it reads.
            let k = n_in + t;
            place[k] = slots.alloc(1);
            dst.push(place[k]);
            op.value_args(&mut args);
            args.sort_unstable();
            args.dedup();
            for &j in &args {
                if last_read[j as usize] == t && !kept[j as usize] {
                    slots.free(place[j as usize], 1);
                }
            }
            if last_read[k] == usize::MAX && !kept[k] {
                slots.free(place[k], 1);
            }
        }
        Registers {
            ops: renamed,
            dst,
            outputs: outputs.iter().map(|&o| place[o as usize]).collect(),
            len: slots.peak(),
        }
    }
}
