//! [`Var`], the recording scalar, and the thread-local recorder it writes to.
//!
//! Operations on constants are folded at record time (the result is a constant), and
//! trivial identities (`x + 0`, `x * 1`, `x * 0`) are simplified away.

use super::op::{Elem, Op};
use crate::scalar::{Scalar, UnaryFn};
use std::cell::RefCell;
use std::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};
use std::sync::Arc;

/// Index marking a [`Var`] that is a constant (not a tape node).
const CONST: u32 = u32::MAX;

/// The operations and registered functions recorded so far on this thread.
pub(crate) struct Recorder {
    /// Recorded operations with the value they had at the recording point.
    pub ops: Vec<(Op, f64)>,
    /// Registered unary functions, referenced by `Op::Apply`.
    pub fns: Vec<Arc<dyn UnaryFn>>,
    /// Identifier of this recording (detects variables from other recordings).
    pub id: u32,
}

thread_local! {
    static RECORDER: RefCell<Option<Recorder>> = const { RefCell::new(None) };
    static NEXT_ID: std::cell::Cell<u32> = const { std::cell::Cell::new(1) };
}

/// Starts a recording on this thread; `Err` if one is active.
pub(crate) fn begin(n_inputs: usize, x0: &[f64]) -> Result<(Vec<Var>, u32), crate::AdError> {
    RECORDER.with(|r| {
        let mut r = r.borrow_mut();
        if r.is_some() {
            return Err(crate::AdError::NestedRecording);
        }
        let id = NEXT_ID.with(|n| {
            let id = n.get();
            n.set(id.wrapping_add(1).max(1));
            id
        });
        let ops = (0..n_inputs)
            .map(|k| (Op::Input(k as u32), x0[k]))
            .collect();
        *r = Some(Recorder {
            ops,
            fns: Vec::new(),
            id,
        });
        let vars = (0..n_inputs)
            .map(|k| Var {
                idx: k as u32,
                val: x0[k],
                rec: id,
            })
            .collect();
        Ok((vars, id))
    })
}

/// Ends the recording on this thread and returns what was recorded.
pub(crate) fn end() -> Option<Recorder> {
    RECORDER.with(|r| r.borrow_mut().take())
}

/// Appends an operation to the active recording.
///
/// # Panics
/// When no recording is active on this thread: a [`Var`] was used outside
/// `Tape::record` or on another thread (a programming error, not a user-input error).
fn push(op: Op, val: f64) -> Var {
    RECORDER.with(|r| {
        let mut r = r.borrow_mut();
        let rec = r
            .as_mut()
            .expect("stride_ad::Var used outside Tape::record (or on another thread)");
        let idx = rec.ops.len() as u32;
        rec.ops.push((op, val));
        Var {
            idx,
            val,
            rec: rec.id,
        }
    })
}

/// Registers a unary function (deduplicated by pointer) and returns its number.
fn register(f: &Arc<dyn UnaryFn>) -> u32 {
    RECORDER.with(|r| {
        let mut r = r.borrow_mut();
        let rec = r
            .as_mut()
            .expect("stride_ad::Var used outside Tape::record (or on another thread)");
        if let Some(k) = rec.fns.iter().position(|g| Arc::ptr_eq(g, f)) {
            return k as u32;
        }
        rec.fns.push(f.clone());
        (rec.fns.len() - 1) as u32
    })
}

/// A scalar that records every operation on the active tape (see `Tape::record`).
///
/// It carries the value at the recording point, so [`Scalar::value`] works, but that
/// value must not steer control flow: the tape replays the recorded operations only.
#[derive(Clone, Copy, Debug)]
pub struct Var {
    /// Node index, or `CONST`.
    pub(crate) idx: u32,
    /// Value at the recording point.
    pub(crate) val: f64,
    /// Recording identifier (0 for constants).
    pub(crate) rec: u32,
}

impl Var {
    #[inline]
    fn constant(c: f64) -> Var {
        Var {
            idx: CONST,
            val: c,
            rec: 0,
        }
    }
    #[inline]
    fn is_const(self) -> bool {
        self.idx == CONST
    }
    /// The node index, materialising a constant as a `Const` node when needed.
    #[inline]
    fn node(self) -> u32 {
        if self.is_const() {
            push(Op::Const(self.val), self.val).idx
        } else {
            self.idx
        }
    }
    /// Whether this variable is a compile-time constant of the recording.
    pub fn is_constant(self) -> bool {
        self.is_const()
    }
    #[inline]
    fn unary(self, e: Elem) -> Var {
        let v = e.value(self.val);
        if self.is_const() {
            Var::constant(v)
        } else {
            push(Op::Unary(self.idx, e), v)
        }
    }
}

impl Add for Var {
    type Output = Var;
    #[inline]
    fn add(self, o: Var) -> Var {
        let v = self.val + o.val;
        match (self.is_const(), o.is_const()) {
            (true, true) => Var::constant(v),
            (true, false) => o + self.val,
            (false, true) => self + o.val,
            (false, false) => push(Op::Add(self.idx, o.idx), v),
        }
    }
}

impl Sub for Var {
    type Output = Var;
    #[inline]
    fn sub(self, o: Var) -> Var {
        let v = self.val - o.val;
        match (self.is_const(), o.is_const()) {
            (true, true) => Var::constant(v),
            (true, false) => {
                if self.val == 0.0 {
                    -o
                } else {
                    push(Op::AddC(push(Op::Neg(o.idx), -o.val).idx, self.val), v)
                }
            }
            (false, true) => self - o.val,
            (false, false) => push(Op::Sub(self.idx, o.idx), v),
        }
    }
}

impl Mul for Var {
    type Output = Var;
    #[inline]
    fn mul(self, o: Var) -> Var {
        let v = self.val * o.val;
        match (self.is_const(), o.is_const()) {
            (true, true) => Var::constant(v),
            (true, false) => o * self.val,
            (false, true) => self * o.val,
            (false, false) => push(Op::Mul(self.idx, o.idx), v),
        }
    }
}

impl Div for Var {
    type Output = Var;
    #[inline]
    fn div(self, o: Var) -> Var {
        let v = self.val / o.val;
        match (self.is_const(), o.is_const()) {
            (true, true) => Var::constant(v),
            (true, false) => push(Op::CDiv(self.val, o.idx), v),
            (false, true) => self / o.val,
            (false, false) => push(Op::Div(self.idx, o.idx), v),
        }
    }
}

impl Neg for Var {
    type Output = Var;
    #[inline]
    fn neg(self) -> Var {
        if self.is_const() {
            Var::constant(-self.val)
        } else {
            push(Op::Neg(self.idx), -self.val)
        }
    }
}

impl Add<f64> for Var {
    type Output = Var;
    #[inline]
    fn add(self, c: f64) -> Var {
        if self.is_const() {
            Var::constant(self.val + c)
        } else if c == 0.0 {
            self
        } else {
            push(Op::AddC(self.idx, c), self.val + c)
        }
    }
}

impl Sub<f64> for Var {
    type Output = Var;
    #[inline]
    fn sub(self, c: f64) -> Var {
        // x - c == x + (-c) exactly in IEEE arithmetic.
        self + (-c)
    }
}

impl Mul<f64> for Var {
    type Output = Var;
    #[inline]
    fn mul(self, c: f64) -> Var {
        if self.is_const() {
            Var::constant(self.val * c)
        } else if c == 1.0 {
            self
        } else if c == -1.0 {
            -self
        } else {
            push(Op::MulC(self.idx, c), self.val * c)
        }
    }
}

impl Div<f64> for Var {
    type Output = Var;
    #[inline]
    fn div(self, c: f64) -> Var {
        if self.is_const() {
            Var::constant(self.val / c)
        } else if c == 1.0 {
            self
        } else {
            push(Op::DivC(self.idx, c), self.val / c)
        }
    }
}

macro_rules! assign_ops {
    ($($tr:ident $f:ident $op:tt $rhs:ty;)*) => {
        $(impl $tr<$rhs> for Var {
            #[inline]
            fn $f(&mut self, o: $rhs) {
                *self = *self $op o;
            }
        })*
    };
}
assign_ops! {
    AddAssign add_assign + Var; SubAssign sub_assign - Var;
    MulAssign mul_assign * Var; DivAssign div_assign / Var;
    AddAssign add_assign + f64; SubAssign sub_assign - f64;
    MulAssign mul_assign * f64; DivAssign div_assign / f64;
}

impl Scalar for Var {
    #[inline]
    fn cst(x: f64) -> Self {
        Var::constant(x)
    }
    #[inline]
    fn value(self) -> f64 {
        self.val
    }
    fn sin(self) -> Self {
        self.unary(Elem::Sin)
    }
    fn cos(self) -> Self {
        self.unary(Elem::Cos)
    }
    fn exp(self) -> Self {
        self.unary(Elem::Exp)
    }
    fn ln(self) -> Self {
        self.unary(Elem::Ln)
    }
    fn sqrt(self) -> Self {
        self.unary(Elem::Sqrt)
    }
    fn tanh(self) -> Self {
        self.unary(Elem::Tanh)
    }
    fn recip(self) -> Self {
        self.unary(Elem::Recip)
    }
    fn powf(self, p: f64) -> Self {
        let v = self.val.powf(p);
        if self.is_const() {
            Var::constant(v)
        } else if p == 0.0 {
            Var::constant(1.0)
        } else if p == 1.0 {
            self
        } else {
            push(Op::Powf(self.idx, p), v)
        }
    }
    fn powi(self, n: i32) -> Self {
        let v = self.val.powi(n);
        if self.is_const() {
            Var::constant(v)
        } else if n == 0 {
            Var::constant(1.0)
        } else if n == 1 {
            self
        } else {
            push(Op::Powi(self.idx, n), v)
        }
    }
    fn fmin(self, o: Self) -> Self {
        let v = f64::min(self.val, o.val);
        if self.is_const() && o.is_const() {
            Var::constant(v)
        } else {
            push(Op::Min(self.node(), o.node()), v)
        }
    }
    fn fmax(self, o: Self) -> Self {
        let v = f64::max(self.val, o.val);
        if self.is_const() && o.is_const() {
            Var::constant(v)
        } else {
            push(Op::Max(self.node(), o.node()), v)
        }
    }
    fn select_pos(cond: Self, pos: Self, nonpos: Self) -> Self {
        if cond.is_const() {
            return if cond.val > 0.0 { pos } else { nonpos };
        }
        let v = if cond.val > 0.0 { pos.val } else { nonpos.val };
        if pos.is_const() && nonpos.is_const() && pos.val.to_bits() == nonpos.val.to_bits() {
            return pos;
        }
        push(Op::Select(cond.idx, pos.node(), nonpos.node()), v)
    }
    fn apply(self, f: &Arc<dyn UnaryFn>) -> Self {
        let v = f.eval(self.val)[0];
        if self.is_const() {
            Var::constant(v)
        } else {
            push(Op::Apply(self.idx, register(f)), v)
        }
    }
}
