//! Hand-written bindings to IPOPT's C interface (`coin/IpStdCInterface.h`, checked against
//! Debian's IPOPT 3.11.9; unchanged in 3.12–3.14 for the functions used here).

use std::ffi::{c_char, c_int, c_void};

/// IPOPT `Number`.
pub type Number = f64;
/// IPOPT `Index` (32-bit).
pub type Index = c_int;
/// IPOPT `Bool` (0 false, nonzero true).
pub type Bool = c_int;
/// Opaque `IpoptProblemInfo`.
#[repr(C)]
pub struct IpoptProblemInfo {
    _private: [u8; 0],
}
/// `IpoptProblem`: handle returned by `CreateIpoptProblem`.
pub type IpoptProblem = *mut IpoptProblemInfo;
/// `UserDataPtr`.
pub type UserDataPtr = *mut c_void;

/// Objective callback.
pub type EvalFCb = unsafe extern "C" fn(Index, *mut Number, Bool, *mut Number, UserDataPtr) -> Bool;
/// Objective-gradient callback.
pub type EvalGradFCb =
    unsafe extern "C" fn(Index, *mut Number, Bool, *mut Number, UserDataPtr) -> Bool;
/// Constraint callback.
pub type EvalGCb =
    unsafe extern "C" fn(Index, *mut Number, Bool, Index, *mut Number, UserDataPtr) -> Bool;
/// Jacobian callback (structure when `values` is null).
pub type EvalJacGCb = unsafe extern "C" fn(
    Index,
    *mut Number,
    Bool,
    Index,
    Index,
    *mut Index,
    *mut Index,
    *mut Number,
    UserDataPtr,
) -> Bool;
/// Hessian-of-Lagrangian callback (structure when `values` is null).
pub type EvalHCb = unsafe extern "C" fn(
    Index,
    *mut Number,
    Bool,
    Number,
    Index,
    *mut Number,
    Bool,
    Index,
    *mut Index,
    *mut Index,
    *mut Number,
    UserDataPtr,
) -> Bool;
/// Per-iteration callback (return 0 to stop).
pub type IntermediateCb = unsafe extern "C" fn(
    Index,
    Index,
    Number,
    Number,
    Number,
    Number,
    Number,
    Number,
    Number,
    Number,
    Index,
    UserDataPtr,
) -> Bool;

/// `enum ApplicationReturnStatus` values.
pub mod status {
    use std::ffi::c_int;
    /// Solve_Succeeded.
    pub const SOLVE_SUCCEEDED: c_int = 0;
    /// Solved_To_Acceptable_Level.
    pub const SOLVED_TO_ACCEPTABLE_LEVEL: c_int = 1;
    /// Infeasible_Problem_Detected.
    pub const INFEASIBLE_PROBLEM_DETECTED: c_int = 2;
    /// Search_Direction_Becomes_Too_Small.
    pub const SEARCH_DIRECTION_BECOMES_TOO_SMALL: c_int = 3;
    /// Diverging_Iterates.
    pub const DIVERGING_ITERATES: c_int = 4;
    /// User_Requested_Stop.
    pub const USER_REQUESTED_STOP: c_int = 5;
    /// Feasible_Point_Found.
    pub const FEASIBLE_POINT_FOUND: c_int = 6;
    /// Maximum_Iterations_Exceeded.
    pub const MAXIMUM_ITERATIONS_EXCEEDED: c_int = -1;
    /// Restoration_Failed.
    pub const RESTORATION_FAILED: c_int = -2;
    /// Error_In_Step_Computation.
    pub const ERROR_IN_STEP_COMPUTATION: c_int = -3;
    /// Maximum_CpuTime_Exceeded.
    pub const MAXIMUM_CPUTIME_EXCEEDED: c_int = -4;
    /// Maximum_WallTime_Exceeded (IPOPT >= 3.14).
    pub const MAXIMUM_WALLTIME_EXCEEDED: c_int = -5;
    /// Not_Enough_Degrees_Of_Freedom.
    pub const NOT_ENOUGH_DEGREES_OF_FREEDOM: c_int = -10;
    /// Invalid_Problem_Definition.
    pub const INVALID_PROBLEM_DEFINITION: c_int = -11;
    /// Invalid_Option.
    pub const INVALID_OPTION: c_int = -12;
    /// Invalid_Number_Detected.
    pub const INVALID_NUMBER_DETECTED: c_int = -13;
}

// Linked by build.rs (pkg-config `ipopt`).
extern "C" {
    /// Creates a problem (bounds are copied); returns null on failure.
    pub fn CreateIpoptProblem(
        n: Index,
        x_l: *mut Number,
        x_u: *mut Number,
        m: Index,
        g_l: *mut Number,
        g_u: *mut Number,
        nele_jac: Index,
        nele_hess: Index,
        index_style: Index,
        eval_f: EvalFCb,
        eval_g: EvalGCb,
        eval_grad_f: EvalGradFCb,
        eval_jac_g: EvalJacGCb,
        eval_h: EvalHCb,
    ) -> IpoptProblem;
    /// Frees a problem.
    pub fn FreeIpoptProblem(problem: IpoptProblem);
    /// Sets a string option; false if unknown or invalid.
    pub fn AddIpoptStrOption(problem: IpoptProblem, keyword: *mut c_char, val: *mut c_char)
        -> Bool;
    /// Sets a numeric option; false if unknown or invalid.
    pub fn AddIpoptNumOption(problem: IpoptProblem, keyword: *mut c_char, val: Number) -> Bool;
    /// Sets an integer option; false if unknown or invalid.
    pub fn AddIpoptIntOption(problem: IpoptProblem, keyword: *mut c_char, val: c_int) -> Bool;
    /// Installs the per-iteration callback.
    pub fn SetIntermediateCallback(problem: IpoptProblem, cb: IntermediateCb) -> Bool;
    /// Solves; `x` holds the start on entry and the solution on exit.
    pub fn IpoptSolve(
        problem: IpoptProblem,
        x: *mut Number,
        g: *mut Number,
        obj_val: *mut Number,
        mult_g: *mut Number,
        mult_x_l: *mut Number,
        mult_x_u: *mut Number,
        user_data: UserDataPtr,
    ) -> c_int;
}
