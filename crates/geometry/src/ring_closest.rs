//! The point of a torus's centre circle nearest to a path segment, as OpenSim 4.x
//! `WrapTorus::findClosestPoint` finds it.
//!
//! OpenSim runs MINPACK's Levenberg–Marquardt solver (`lmdif`: one unknown, one residual,
//! forward-difference derivative, tolerances 1e-4, initial step bound 0.2, at most 500
//! evaluations) from the segment's first point and again from its second, on the
//! parameter `u` [m] along the segment. Its residual is meant to be the derivative of the
//! squared distance to the circle but weighs the circle term twice: its roots are the
//! points nearest to the circle of twice the radius. Which root the solver reaches
//! depends on its steps, so they are reproduced here (MINPACK's algorithm for n = m = 1).
//! The better of the two results is taken (nearer to the circle; on the active half with
//! a quadrant) and projected radially onto the circle.

use stride_model::WrapQuadrant;

/// Relative tolerances of the solver on the residual and on the step.
const TOL: f64 = 1e-4;
/// Initial step bound factor.
const FACTOR: f64 = 0.2;
/// Largest number of residual evaluations.
const MAX_EVALUATIONS: usize = 500;

/// OpenSim's residual at `u` [m] along the line from `p1` towards `p2`, for the circle of
/// `radius` [m] about the z axis in the plane z = 0.
fn residual(p1: [f64; 3], n: [f64; 3], radius: f64, u: f64) -> f64 {
    let c2 = 2.0 * (p1[0] * n[0] + p1[1] * n[1] + p1[2] * n[2]);
    let c3 = p1[0] * n[0] + p1[1] * n[1];
    let c4 = n[0] * n[0] + n[1] * n[1];
    let c5 = p1[0] * p1[0] + p1[1] * p1[1];
    c2 + 2.0 * u
        - 2.0 * radius * (2.0 * c4 * u + 2.0 * c3) / (u * u * c4 + 2.0 * c3 * u + c5).sqrt()
}

/// The point of the circle of `radius` about the z axis nearest to the segment
/// `p1`–`p2` (torus frame [m]) by OpenSim's rules, or `None` when a quadrant rejects both
/// candidates (OpenSim then does not wrap).
pub(crate) fn closest_on_ring(
    p1: [f64; 3],
    p2: [f64; 3],
    radius: f64,
    quadrant: Option<WrapQuadrant>,
) -> Option<[f64; 3]> {
    let d = [p2[0] - p1[0], p2[1] - p1[1], p2[2] - p1[2]];
    let mag = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let candidate = |start: [f64; 3], sign: f64| {
        let n = d.map(|v| sign * v / mag);
        let u = minimise(|u| residual(start, n, radius, u));
        let a: [f64; 3] = std::array::from_fn(|k| start[k] + u * n[k]);
        let h = (a[0] * a[0] + a[1] * a[1]).sqrt();
        let dist =
            (a[0] * a[0] + a[1] * a[1] + a[2] * a[2] + radius * radius - 2.0 * radius * h).sqrt();
        (a, dist)
    };
    let (a1, d1) = candidate(p1, 1.0);
    let (a2, d2) = candidate(p2, -1.0);
    let first = match quadrant {
        None => d1 < d2,
        Some(q) => {
            let on = |a: [f64; 3]| crate::wrap_shapes::dsign(a[q.axis]) == q.sign;
            match (on(a1), on(a2)) {
                (true, true) => d1 < d2,
                (true, false) => true,
                (false, true) => false,
                (false, false) => return None,
            }
        }
    };
    let a = if first { a1 } else { a2 };
    let h = (a[0] * a[0] + a[1] * a[1]).sqrt();
    Some([a[0] * radius / h, a[1] * radius / h, 0.0])
}

/// MINPACK's `lmdif` for one unknown and one residual `f`, from 0 with OpenSim's
/// settings: the solution.
fn minimise(f: impl Fn(f64) -> f64) -> f64 {
    let epsmch = f64::EPSILON;
    let h_rel = epsmch.sqrt();
    let mut x = 0.0;
    let mut fx = f(x);
    let mut evaluations = 1;
    let mut fnorm = fx.abs();
    let (mut par, mut delta, mut diag, mut xnorm) = (0.0, 0.0, 0.0f64, 0.0);
    let mut first = true;
    loop {
        let h = if h_rel * x.abs() == 0.0 {
            h_rel
        } else {
            h_rel * x.abs()
        };
        let jac = (f(x + h) - fx) / h;
        evaluations += 1;
        // QR of the 1×1 Jacobian: R = −J, Qᵀf = −f (no reflection when J = 0).
        let acnorm = jac.abs();
        let (r, qtf) = if jac != 0.0 { (-jac, -fx) } else { (0.0, fx) };
        if first {
            diag = if acnorm == 0.0 { 1.0 } else { acnorm };
            xnorm = (diag * x).abs();
            delta = if FACTOR * xnorm == 0.0 {
                FACTOR
            } else {
                FACTOR * xnorm
            };
        }
        let gnorm = if fnorm != 0.0 && acnorm != 0.0 {
            (r * qtf / fnorm).abs() / acnorm
        } else {
            0.0
        };
        if gnorm <= 0.0 {
            return x;
        }
        diag = diag.max(acnorm);
        loop {
            let (p, new_par) = lm_step(r, diag, qtf, delta, par);
            par = new_par;
            let step = -p;
            let trial = x + step;
            let pnorm = (diag * step).abs();
            if first {
                delta = delta.min(pnorm);
            }
            let ft = f(trial);
            evaluations += 1;
            let fnorm1 = ft.abs();
            let actred = if 0.1 * fnorm1 < fnorm {
                1.0 - (fnorm1 / fnorm).powi(2)
            } else {
                -1.0
            };
            let temp1 = (r * step).abs() / fnorm;
            let temp2 = par.sqrt() * pnorm / fnorm;
            let prered = temp1 * temp1 + temp2 * temp2 / 0.5;
            let dirder = -(temp1 * temp1 + temp2 * temp2);
            let ratio = if prered != 0.0 { actred / prered } else { 0.0 };
            if ratio <= 0.25 {
                let mut t = if actred >= 0.0 {
                    0.5
                } else {
                    0.5 * dirder / (dirder + 0.5 * actred)
                };
                if 0.1 * fnorm1 >= fnorm || t < 0.1 {
                    t = 0.1;
                }
                delta = t * delta.min(pnorm / 0.1);
                par /= t;
            } else if par == 0.0 || ratio >= 0.75 {
                delta = pnorm / 0.5;
                par *= 0.5;
            }
            let success = ratio >= 1e-4;
            if success {
                x = trial;
                fx = ft;
                xnorm = (diag * x).abs();
                fnorm = fnorm1;
                first = false;
            }
            let small_reduction = actred.abs() <= TOL && prered <= TOL && 0.5 * ratio <= 1.0;
            if small_reduction || delta <= TOL * xnorm || evaluations >= MAX_EVALUATIONS {
                return x;
            }
            let exhausted = actred.abs() <= epsmch && prered <= epsmch && 0.5 * ratio <= 1.0;
            if exhausted || delta <= epsmch * xnorm || gnorm <= epsmch {
                return x;
            }
            if success {
                break;
            }
        }
    }
}

/// MINPACK's `lmpar` for n = 1: the step `p` solving `(R² + par·D²) p = R·Qᵀf` with
/// `|D p|` within 10 % of `delta` (or the Gauss–Newton step when it is shorter), and the
/// Levenberg parameter `par`.
fn lm_step(r: f64, d: f64, qtf: f64, delta: f64, par0: f64) -> (f64, f64) {
    let dwarf = f64::MIN_POSITIVE;
    let gauss_newton = if r != 0.0 { qtf / r } else { 0.0 };
    let mut dxnorm = (d * gauss_newton).abs();
    let mut fp = dxnorm - delta;
    if fp <= 0.1 * delta {
        return (gauss_newton, 0.0);
    }
    let mut parl = 0.0;
    if r != 0.0 {
        let w = d * (d * gauss_newton / dxnorm) / r;
        parl = ((fp / delta) / w.abs()) / w.abs();
    }
    let gnorm = (r * qtf / d).abs();
    let mut paru = gnorm / delta;
    if paru == 0.0 {
        paru = dwarf / delta.min(0.1);
    }
    let mut par = par0.max(parl).min(paru);
    if par == 0.0 {
        par = gnorm / dxnorm;
    }
    let mut iter = 0;
    loop {
        iter += 1;
        if par == 0.0 {
            par = dwarf.max(0.001 * paru);
        }
        let s2 = r * r + par * d * d;
        let x = if s2 != 0.0 { r * qtf / s2 } else { 0.0 };
        dxnorm = (d * x).abs();
        let previous = fp;
        fp = dxnorm - delta;
        if fp.abs() <= 0.1 * delta
            || (parl == 0.0 && fp <= previous && previous < 0.0)
            || iter == 10
        {
            return (x, par);
        }
        let w = (d * (d * x / dxnorm) / s2.sqrt()).abs();
        let parc = ((fp / delta) / w) / w;
        if fp > 0.0 {
            parl = parl.max(par);
        }
        if fp < 0.0 {
            paru = paru.min(par);
        }
        par = parl.max(par + parc);
    }
}
