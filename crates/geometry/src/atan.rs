//! The arc tangent as a registered one-dimensional function, so that angles on wrap
//! surfaces are generic over the scalar.

use std::sync::{Arc, OnceLock};
use stride_ad::UnaryFn;

/// `atan(x)` [rad] with its first two derivatives.
#[derive(Debug)]
struct Atan;

impl UnaryFn for Atan {
    fn eval(&self, x: f64) -> [f64; 3] {
        let d = 1.0 / (1.0 + x * x);
        [x.atan(), d, -2.0 * x * d * d]
    }
}

/// The shared arc-tangent function for [`stride_ad::Scalar::apply`].
pub(crate) fn atan() -> &'static Arc<dyn UnaryFn> {
    static F: OnceLock<Arc<dyn UnaryFn>> = OnceLock::new();
    F.get_or_init(|| Arc::new(Atan))
}
