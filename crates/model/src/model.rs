//! The immutable description of a musculoskeletal model.
//!
//! A [`Model`] is plain data (serialisable): bodies, joints, coordinates, muscles, contact
//! spheres, actuators and passive joint elements. Algorithms are free functions over a
//! model and a workspace (see [`crate::multibody`]), in the style of Pinocchio.
//!
//! Frames follow OpenSim: ground x forward, y up, z to the right. Units are SI
//! (m, kg, s, N, rad) throughout.

use serde::{Deserialize, Serialize};

/// Index of a body in [`Model::bodies`]; index 0 is always the ground.
pub type BodyId = usize;
/// Index of a coordinate in [`Model::coordinates`].
pub type CoordId = usize;

/// A whole musculoskeletal model.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Model {
    /// Model name (from the `.osim` `Model` element).
    pub name: String,
    /// Gravity vector in ground [m s⁻²].
    pub gravity: [f64; 3],
    /// Rigid bodies; `bodies[0]` is the ground (mass 0).
    pub bodies: Vec<Body>,
    /// Joints in topological order: a joint's parent body is the ground or the child of an
    /// earlier joint. Every non-ground body is the child of exactly one joint.
    pub joints: Vec<Joint>,
    /// Generalised coordinates, in the order of the model's state vectors.
    pub coordinates: Vec<Coordinate>,
    /// Hill-type muscles with their paths.
    pub muscles: Vec<Muscle>,
    /// Surfaces fixed on bodies that muscle paths wrap over (OpenSim `WrapObjectSet`s).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub wrap_objects: Vec<WrapObject>,
    /// Contact spheres interacting with the ground half-space.
    pub contacts: Vec<ContactSphere>,
    /// Ideal coordinate actuators (torque or force generators).
    pub actuators: Vec<CoordinateActuator>,
    /// Passive joint torques (exponential limit springs and damping) per coordinate.
    pub passive_torques: Vec<PassiveJointTorque>,
    /// Polynomial muscle–tendon geometry, one entry per muscle (same order as `muscles`);
    /// empty when the model has not been fitted.
    pub path_polynomials: Vec<Option<PathPolynomial>>,
    /// Elements of the source file that were not imported, reported to the user.
    pub unsupported: Vec<UnsupportedElement>,
    /// Passive elastic elements along a path (OpenSim `Ligament`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ligaments: Vec<Ligament>,
    /// Coordinates given as functions of other coordinates (OpenSim
    /// `CoordinateCouplerConstraint`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub couplers: Vec<CoordinateCoupler>,
    /// Generalised forces of one coordinate (OpenSim `CoordinateLimitForce`,
    /// `SpringGeneralizedForce`, `ExpressionBasedCoordinateForce`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub coordinate_forces: Vec<CoordinateForce>,
    /// The OpenSim model file this model was imported from (result folders ship a copy of
    /// it); `None` for the built-in model and for models built in code.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub source_file: Option<std::path::PathBuf>,
    /// Bounds on the horizontal distances between body origins that a gait problem keeps
    /// (anti-clipping constraints, from the model's settings file).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub distance_constraints: Vec<DistanceConstraint>,
    /// Height [m] of the pelvis origin above the ground when the model stands upright, when
    /// its source gives one (the paper's 0.9385 m for the built-in model, a settings file's
    /// `standing_pelvis_height`); `None`: a gait problem derives it from the default pose.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub standing_pelvis_height: Option<f64>,
}

/// A rigid body.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Body {
    /// Body name (OpenSim `Body` name).
    pub name: String,
    /// Mass [kg].
    pub mass: f64,
    /// Centre of mass in the body frame [m].
    pub com: [f64; 3],
    /// Inertia about the centre of mass in body axes [kg m²]: `[xx, yy, zz, xy, xz, yz]`.
    pub inertia: [f64; 6],
}

/// A rigid transform: rotation (body-fixed X–Y–Z Euler angles, OpenSim convention) and
/// translation, from a body frame to a frame fixed on it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Offset {
    /// Position of the frame origin in the body frame [m].
    pub location: [f64; 3],
    /// Orientation as body-fixed X–Y–Z Euler angles [rad].
    pub orientation: [f64; 3],
}

/// A joint connecting a parent body to a child body.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Joint {
    /// Joint name.
    pub name: String,
    /// Parent body.
    pub parent: BodyId,
    /// Child body.
    pub child: BodyId,
    /// Joint frame F fixed on the parent.
    pub frame_in_parent: Offset,
    /// Joint frame M fixed on the child.
    pub frame_in_child: Offset,
    /// Kinematics of M relative to F.
    pub kind: JointKind,
}

/// How the child frame M moves relative to the parent frame F.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, Serialize, Deserialize)]
pub enum JointKind {
    /// No relative motion.
    Weld,
    /// OpenSim `CustomJoint` (Simbody function-based mobiliser): three rotations, applied
    /// as successive body-fixed rotations about `rotations[k].axis` (axes in F), then
    /// three translations along axes fixed in F.
    Custom {
        /// Rotation axes 1–3 with their coordinate functions.
        rotations: [TransformAxis; 3],
        /// Translation axes 1–3 with their coordinate functions.
        translations: [TransformAxis; 3],
    },
}

/// One axis of a `SpatialTransform`: a unit direction and the function of coordinates
/// that gives the angle [rad] or displacement [m] along it.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct TransformAxis {
    /// Unit axis, expressed in the joint's parent frame F.
    pub axis: [f64; 3],
    /// The coordinate the function reads, if any (functions of several coordinates are
    /// not supported by the importer and are reported).
    pub coordinate: Option<CoordId>,
    /// Angle or displacement as a function of the coordinate value.
    pub function: Function,
}

/// A function of one variable, as in OpenSim's function set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Function {
    /// `f(x) = value`.
    Constant(f64),
    /// `f(x) = slope x + intercept`.
    Linear {
        /// Slope.
        slope: f64,
        /// Value at x = 0.
        intercept: f64,
    },
    /// OpenSim `SimmSpline`: cubic spline through the knots `(x, y)` with Forsythe–Malcolm–Moler end conditions (not natural), linear extrapolation. OpenSim 4 reads a
    /// `NaturalCubicSpline` element as this type too.
    SimmSpline {
        /// Knot abscissae (strictly increasing).
        x: Vec<f64>,
        /// Knot ordinates.
        y: Vec<f64>,
    },
    /// OpenSim `PiecewiseLinearFunction`: straight lines between the knots `(x, y)`,
    /// extended with the first and last slope outside them.
    PiecewiseLinear {
        /// Knot abscissae (strictly increasing).
        x: Vec<f64>,
        /// Knot ordinates.
        y: Vec<f64>,
    },
    /// `f(x) = Σ c_k x^(n-1-k)` (OpenSim `PolynomialFunction`, highest power first).
    Polynomial {
        /// Coefficients, highest power first.
        coefficients: Vec<f64>,
    },
    /// `f(x) = scale · g(x)` (OpenSim `MultiplierFunction`).
    Multiplier {
        /// Scale factor.
        scale: f64,
        /// The scaled function.
        function: Box<Function>,
    },
}

/// Whether a coordinate is an angle or a displacement.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum MotionType {
    /// Angle [rad].
    Rotational,
    /// Displacement [m].
    Translational,
    /// Coupled (not supported by the importer).
    Coupled,
}

/// A generalised coordinate.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Coordinate {
    /// Coordinate name (OpenSim).
    pub name: String,
    /// Joint that owns the coordinate.
    pub joint: usize,
    /// Angle or displacement.
    pub motion_type: MotionType,
    /// Allowed range `[min, max]` [rad or m].
    pub range: [f64; 2],
    /// Default value [rad or m].
    pub default_value: f64,
    /// Locked at its default value.
    pub locked: bool,
}

/// Hill-type muscle model named in the source file.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum MuscleKind {
    /// OpenSim `Thelen2003Muscle`.
    Thelen2003,
    /// OpenSim `Millard2012EquilibriumMuscle`.
    Millard2012Equilibrium,
    /// OpenSim `Millard2012AccelerationMuscle`.
    Millard2012Acceleration,
    /// OpenSim `DeGrooteFregly2016Muscle`.
    DeGrooteFregly2016,
    /// OpenSim `RigidTendonMuscle`.
    RigidTendon,
}

/// A muscle–tendon unit: Hill parameters and its path.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Muscle {
    /// Muscle name.
    pub name: String,
    /// Muscle model of the source file (the contraction dynamics used by stride are
    /// always De Groote 2016; the parameters carry over).
    pub kind: MuscleKind,
    /// Maximal isometric force F_max [N].
    pub max_isometric_force: f64,
    /// Optimal fibre length l_opt [m].
    pub optimal_fiber_length: f64,
    /// Tendon slack length l_ts [m].
    pub tendon_slack_length: f64,
    /// Pennation angle at optimal fibre length [rad].
    pub pennation_angle_at_optimal: f64,
    /// Maximal contraction velocity [l_opt s⁻¹] (10 in the paper).
    pub max_contraction_velocity: f64,
    /// Path points from origin to insertion (empty when `path_function` gives the length).
    pub path: Vec<PathPoint>,
    /// Wrap objects the path wraps over, in the order OpenSim applies them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub wraps: Vec<PathWrap>,
    /// The muscle–tendon length [m] as the model's own polynomial of coordinates (OpenSim
    /// `FunctionBasedPath` with a `MultivariatePolynomialFunction`): the muscle's geometry,
    /// used as it is (moment arms −∂l/∂q), no path points and no fit.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path_function: Option<PathPolynomial>,
    /// Fraction of slow-twitch fibres (0–1) for the metabolic models (0.5 when unknown).
    pub slow_twitch_fraction: f64,
    /// Specific tension σ [Pa] used for the muscle mass (0.25 MPa when unknown).
    pub specific_tension: f64,
    /// Factor on the tendon stiffness: the muscle's k_T is the problem's k_T (35) times
    /// this, with the tendon curve shift recomputed (PredSim's `tendon_stiff_scale`; 1
    /// when unset).
    #[serde(default = "unit_scale", skip_serializing_if = "is_unit")]
    pub tendon_stiffness_scale: f64,
    /// Shift λ of the passive fibre force–length curve, `f_PE` evaluated at
    /// `(l̃_M − λ)` instead of `(l̃_M − 1)` (PredSim's `muscle_pass_stiff_shift`; 1 when
    /// unset).
    #[serde(default = "unit_scale", skip_serializing_if = "is_unit")]
    pub passive_fibre_shift: f64,
    /// Scale κ of the passive fibre curve's exponent, `exp(4κ(l̃_M − λ)/0.6)` (PredSim's
    /// `muscle_pass_stiff_scale`; 1 when unset).
    #[serde(default = "unit_scale", skip_serializing_if = "is_unit")]
    pub passive_fibre_scale: f64,
    /// Width scale w ≥ 1 of the active fibre force–length curve: `f_L` is evaluated at
    /// `(l̃_M − 1)/w + 1`, widening the curve about its peak (OpenSim
    /// `DeGrooteFregly2016Muscle` `active_force_width_scale`; 1 when unset).
    #[serde(default = "unit_scale", skip_serializing_if = "is_unit")]
    pub active_force_width_scale: f64,
    /// Whether the passive fibre force is zero at every length (OpenSim
    /// `DeGrooteFregly2016Muscle` `ignore_passive_fiber_force`; false when unset).
    #[serde(default, skip_serializing_if = "is_false")]
    pub ignore_passive_fiber_force: bool,
    /// Steepness b of the smooth conditionals `½(1 + tanh(b x))` in the Bhargava (2004)
    /// metabolic rate (10 in the paper; PredSim's `b`).
    #[serde(
        default = "default_metabolic_smoothing",
        skip_serializing_if = "is_default_metabolic_smoothing"
    )]
    pub metabolic_smoothing: f64,
}

fn unit_scale() -> f64 {
    1.0
}

/// The paper's steepness of the metabolic smooth conditionals (10).
pub fn default_metabolic_smoothing() -> f64 {
    10.0
}

fn is_false(b: &bool) -> bool {
    !*b
}

fn is_unit(x: &f64) -> bool {
    *x == 1.0
}

fn is_default_metabolic_smoothing(x: &f64) -> bool {
    *x == default_metabolic_smoothing()
}

/// Polynomial approximation of a muscle–tendon length:
/// `l_MT(q) = Σ_k c_k Π_j q[coordinates[j]]^exponents[k][j]` [m], with q in rad (or m).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PathPolynomial {
    /// Coordinates the muscle spans, in the order of the exponent tuples.
    pub coordinates: Vec<CoordId>,
    /// Total polynomial order p.
    pub order: u32,
    /// Exponent tuple of each monomial (one exponent per spanned coordinate).
    pub exponents: Vec<Vec<u8>>,
    /// Coefficient of each monomial [m].
    pub coefficients: Vec<f64>,
    /// RMS error of the fitted length over the fitting samples [m], if known.
    pub rmse_length: Option<f64>,
    /// Largest RMS error of the fitted moment arms over the spanned coordinates [m], if known.
    pub rmse_moment_arm: Option<f64>,
}

/// A point of a muscle path, fixed on a body.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct PathPoint {
    /// Point name.
    pub name: String,
    /// Body the point is attached to.
    pub body: BodyId,
    /// Location in the body frame [m] (for moving points: used only where no function is given).
    pub location: [f64; 3],
    /// Fixed, conditional or moving.
    pub kind: PathPointKind,
}

/// The kind of a path point.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub enum PathPointKind {
    /// Always active, fixed location.
    Fixed,
    /// Active only while `coordinate` lies within `range` (inclusive) [rad or m].
    Conditional {
        /// Coordinate deciding activity.
        coordinate: CoordId,
        /// Active range `[min, max]`.
        range: [f64; 2],
    },
    /// Location components given as functions of coordinates (OpenSim `MovingPathPoint`).
    Moving {
        /// x, y, z components: `Some((coordinate, function))`, or `None` for the fixed
        /// component of `location`.
        components: [Option<(CoordId, Function)>; 3],
    },
}

/// A surface fixed on a body that muscle paths wrap over (OpenSim `WrapObject`).
///
/// The surface is placed in its body by `rotation` (body-fixed X–Y–Z Euler angles [rad])
/// and `translation` [m]; cylinder and torus axes are the z axis of that frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct WrapObject {
    /// Wrap object name (unique in the model).
    pub name: String,
    /// Body the surface is fixed to.
    pub body: BodyId,
    /// Orientation in the body as body-fixed X–Y–Z Euler angles [rad].
    pub rotation: [f64; 3],
    /// Origin in the body frame [m].
    pub translation: [f64; 3],
    /// Side of the surface a path may wrap over; `None` for all sides.
    pub quadrant: Option<WrapQuadrant>,
    /// Whether paths wrap over it (OpenSim `active`).
    pub active: bool,
    /// Shape and dimensions.
    pub shape: WrapShape,
}

/// The active side of a wrap object: the half-space `sign · x[axis] > 0` of its frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct WrapQuadrant {
    /// Axis of the wrap frame: 0 = x, 1 = y, 2 = z.
    pub axis: usize,
    /// +1 or −1.
    pub sign: i8,
}

/// Shape of a wrap object, dimensions in metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum WrapShape {
    /// Circular cylinder along z, centred on the origin.
    Cylinder {
        /// Radius [m].
        radius: f64,
        /// Length along z [m].
        length: f64,
    },
    /// Sphere centred on the origin.
    Sphere {
        /// Radius [m].
        radius: f64,
    },
    /// Ellipsoid centred on the origin with semi-axes along x, y, z.
    Ellipsoid {
        /// Semi-axes [m].
        radii: [f64; 3],
    },
    /// Torus around the z axis.
    Torus {
        /// Inner radius (of the tube) [m].
        inner_radius: f64,
        /// Outer radius (centre of the tube from the axis) [m].
        outer_radius: f64,
    },
}

impl WrapShape {
    /// OpenSim class name of the shape (`WrapCylinder`, …).
    pub fn class_name(&self) -> &'static str {
        match self {
            Self::Cylinder { .. } => "WrapCylinder",
            Self::Sphere { .. } => "WrapSphere",
            Self::Ellipsoid { .. } => "WrapEllipsoid",
            Self::Torus { .. } => "WrapTorus",
        }
    }
}

/// One wrap of a muscle path over a wrap object (OpenSim `PathWrap`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PathWrap {
    /// Index in [`Model::wrap_objects`].
    pub object: usize,
    /// First and last path point considered (1-based indices into the muscle's full list
    /// of path points, active or not); a value below 1 means the first / last point.
    pub range: [i32; 2],
    /// OpenSim wrapping method (`hybrid`, `midpoint` or `axial`; used by ellipsoids).
    pub method: String,
}

/// Parameters of the smooth Hunt–Crossley sphere–plane contact (OpenSim
/// `SmoothSphereHalfSpaceForce`). Fields left out of a file take the paper's values.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ContactParameters {
    /// Plane-strain modulus E [N m⁻²].
    pub stiffness: f64,
    /// Hunt–Crossley dissipation c [s m⁻¹].
    pub dissipation: f64,
    /// Static friction coefficient μ_s.
    pub static_friction: f64,
    /// Dynamic friction coefficient μ_d.
    pub dynamic_friction: f64,
    /// Viscous friction coefficient μ_v [s m⁻¹].
    pub viscous_friction: f64,
    /// Transition velocity v_t [m s⁻¹].
    pub transition_velocity: f64,
    /// Smoothing constant c_f added under the square roots [m² or m² s⁻²].
    pub constant_contact_force: f64,
    /// Steepness of the Hertz smoothing b_d [m⁻¹].
    pub hertz_smoothing: f64,
    /// Steepness of the Hunt–Crossley smoothing b_v [s m⁻¹].
    pub hunt_crossley_smoothing: f64,
    /// Half-width ε of a smooth transition of min(v_slip / v_t, 1) in the friction law
    /// (dimensionless, a fraction of v_t); 0 (the default, absent from model files) keeps
    /// OpenSim's exact minimum, which has a kink at v_slip = v_t.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub friction_transition_smoothing: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

impl Default for ContactParameters {
    /// The parameters of the paper (Falisse et al. 2019, generic contact model).
    fn default() -> Self {
        Self {
            stiffness: 1.0e6,
            dissipation: 2.0,
            static_friction: 0.8,
            dynamic_friction: 0.8,
            viscous_friction: 0.5,
            transition_velocity: 0.2,
            constant_contact_force: 1.0e-5,
            hertz_smoothing: 300.0,
            hunt_crossley_smoothing: 50.0,
            friction_transition_smoothing: 0.0,
        }
    }
}

/// A contact sphere fixed on a body, in contact with the ground half-space.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ContactSphere {
    /// Name of the force element (e.g. `contact_sphere_1_r`).
    pub name: String,
    /// Body carrying the sphere.
    pub body: BodyId,
    /// Sphere centre in the body frame [m].
    pub location: [f64; 3],
    /// Radius [m].
    pub radius: f64,
    /// Contact law parameters.
    pub parameters: ContactParameters,
    /// A point of the ground plane, in ground [m].
    pub plane_point: [f64; 3],
    /// Outward unit normal of the ground half-space, in ground.
    pub plane_normal: [f64; 3],
}

/// An ideal actuator of one coordinate: generalised force = `optimal_force · control`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CoordinateActuator {
    /// Actuator name.
    pub name: String,
    /// Actuated coordinate.
    pub coordinate: CoordId,
    /// Force or torque per unit control [N m or N].
    pub optimal_force: f64,
    /// Control bounds `[min, max]`.
    pub control_range: [f64; 2],
    /// Activation time constant τ [s] of an OpenSim `ActivationCoordinateActuator`
    /// (first-order dynamics ȧ = (u − a)/τ, generalised force = `optimal_force · a`);
    /// `None` for a plain `CoordinateActuator` (force = `optimal_force · control`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub activation_time_constant: Option<f64>,
}

/// An OpenSim `Ligament`: a passive element along a path whose tension [N] is
/// `pcsa_force · force_length(l / resting_length)` when its length `l` exceeds
/// `resting_length`, and zero otherwise.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Ligament {
    /// Element name.
    pub name: String,
    /// Length below which the ligament is slack [m].
    pub resting_length: f64,
    /// Force scale of the normalised force–length curve [N].
    pub pcsa_force: f64,
    /// Normalised force–length curve: tension / `pcsa_force` as a function of
    /// length / `resting_length` (dimensionless).
    pub force_length: Function,
    /// Path points from origin to insertion.
    pub path: Vec<PathPoint>,
    /// Wrap objects the path wraps over, in the order OpenSim applies them.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub wraps: Vec<PathWrap>,
    /// Polynomial fit of the path length [m] over the coordinates the ligament spans
    /// (from the geometry file); `None` when the model has not been fitted.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub path_polynomial: Option<PathPolynomial>,
}

/// A dependent coordinate that follows an independent one:
/// `q[dependent] = function(q[independent])` (OpenSim `CoordinateCouplerConstraint`).
/// The multibody layer eliminates the dependent coordinate by substitution: its value,
/// speed and acceleration follow from the independent coordinate's, and its generalised
/// force is carried by the independent coordinate.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct CoordinateCoupler {
    /// Constraint name.
    pub name: String,
    /// Coordinate given by the function.
    pub dependent: CoordId,
    /// Coordinate the function reads.
    pub independent: CoordId,
    /// Dependent value [rad or m] as a function of the independent value [rad or m].
    pub function: Function,
}

/// A generalised force acting on one coordinate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CoordinateForce {
    /// Element name.
    pub name: String,
    /// The coordinate it acts on.
    pub coordinate: CoordId,
    /// Its force law.
    pub law: CoordinateForceLaw,
}

/// Force laws of [`CoordinateForce`], as OpenSim defines them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum CoordinateForceLaw {
    /// OpenSim `CoordinateLimitForce`: stiff springs beyond `[lower_limit, upper_limit]`
    /// that switch on smoothly over `transition`, plus damping that switches on with them.
    /// Stiffnesses are in N m per degree (rotational) or N per m (translational) and the
    /// limits and transition in degrees or m, as in the file; `rotational` tells which.
    CoordinateLimit {
        /// Stiffness beyond the upper limit [N m deg⁻¹ or N m⁻¹].
        upper_stiffness: f64,
        /// Upper limit [deg or m].
        upper_limit: f64,
        /// Stiffness beyond the lower limit [N m deg⁻¹ or N m⁻¹].
        lower_stiffness: f64,
        /// Lower limit [deg or m].
        lower_limit: f64,
        /// Damping [N m s deg⁻¹ or N s m⁻¹].
        damping: f64,
        /// Width over which the springs and damping switch on [deg or m].
        transition: f64,
        /// Whether the coordinate is an angle (file values in degrees).
        rotational: bool,
    },
    /// OpenSim `ExpressionBasedCoordinateForce`: `τ = expression(q, q̇)` [N m or N], an
    /// expression of the variables `q` [rad or m] and `qdot` [rad s⁻¹ or m s⁻¹].
    Expression(crate::expression::Expression),
    /// OpenSim `SpringGeneralizedForce`:
    /// `τ = −stiffness (q − rest_length) − viscosity q̇` [N m or N].
    Spring {
        /// Stiffness [N m rad⁻¹ or N m⁻¹].
        stiffness: f64,
        /// Rest value of the coordinate [rad or m].
        rest_length: f64,
        /// Viscous damping [N m s rad⁻¹ or N s m⁻¹].
        viscosity: f64,
    },
}

/// Passive joint torque of one coordinate:
/// `T = k1 exp(k2 (q − θ2)) + k3 exp(k4 (q − θ1)) − damping · q̇` [N m]; the exponential
/// terms are the limit torque.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PassiveJointTorque {
    /// The coordinate.
    pub coordinate: CoordId,
    /// Stiffness coefficients `[k1, k2, k3, k4]` ([N m], [rad⁻¹], [N m], [rad⁻¹]).
    pub k: [f64; 4],
    /// Thresholds `[θ1 (lower), θ2 (upper)]` [rad].
    pub theta: [f64; 2],
    /// Linear damping [N m s rad⁻¹].
    pub damping: f64,
}

impl PassiveJointTorque {
    /// Whether the element has a limit torque (a non-zero exponential term).
    pub fn has_limit(&self) -> bool {
        self.k[0] != 0.0 || self.k[2] != 0.0
    }
}

/// An element of the source file that the importer did not turn into model data.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct UnsupportedElement {
    /// XML element type (e.g. `WrapCylinder`).
    pub element: String,
    /// Name attribute, if any.
    pub name: String,
    /// Path of the element in the document, e.g. `Model/ForceSet/objects/PointActuator`.
    pub path: String,
    /// Line in the source file (1-based).
    pub line: usize,
    /// Why it was not imported.
    pub reason: String,
}

impl Default for Model {
    /// An empty model: only the ground body, gravity −9.81 m s⁻² along y.
    fn default() -> Self {
        Self {
            name: String::new(),
            gravity: [0.0, -9.81, 0.0],
            bodies: vec![Body {
                name: "ground".into(),
                mass: 0.0,
                com: [0.0; 3],
                inertia: [0.0; 6],
            }],
            joints: Vec::new(),
            coordinates: Vec::new(),
            muscles: Vec::new(),
            wrap_objects: Vec::new(),
            contacts: Vec::new(),
            actuators: Vec::new(),
            passive_torques: Vec::new(),
            path_polynomials: Vec::new(),
            unsupported: Vec::new(),
            ligaments: Vec::new(),
            couplers: Vec::new(),
            coordinate_forces: Vec::new(),
            source_file: None,
            distance_constraints: Vec::new(),
            standing_pelvis_height: None,
        }
    }
}

impl Model {
    /// Total mass of all bodies [kg].
    pub fn total_mass(&self) -> f64 {
        self.bodies.iter().map(|b| b.mass).sum()
    }
    /// Index of the body with this name.
    pub fn body_index(&self, name: &str) -> Option<BodyId> {
        self.bodies.iter().position(|b| b.name == name)
    }
    /// Index of the coordinate with this name.
    pub fn coordinate_index(&self, name: &str) -> Option<CoordId> {
        self.coordinates.iter().position(|c| c.name == name)
    }
    /// Index of the muscle with this name.
    pub fn muscle_index(&self, name: &str) -> Option<usize> {
        self.muscles.iter().position(|m| m.name == name)
    }
    /// Index of the joint whose child is `body`.
    pub fn joint_of_body(&self, body: BodyId) -> Option<usize> {
        self.joints.iter().position(|j| j.child == body)
    }
}

/// Keep two body origins apart in the horizontal (ground x–z) plane.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DistanceConstraint {
    /// The two bodies whose origins are kept apart.
    pub bodies: [String; 2],
    /// Minimum distance [m].
    pub min: f64,
    /// Maximum distance [m] (2 m: inactive).
    #[serde(default = "default_max_distance")]
    pub max: f64,
}

fn default_max_distance() -> f64 {
    2.0
}
