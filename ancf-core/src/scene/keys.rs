//! Every key of a scene file, declared once: its table, type, unit, default,
//! range, the Python arguments that take the same value, and one line of
//! doc. The schema (schema.rs), the value checks, the Python signatures and
//! stub, and the key tables of `docs/scene.md` are tested against this list
//! (`ancf-core/tests/scene_keys.rs`), so none of them can drift from it
//! unnoticed: a new key is declared here first.

/// What a key holds, as written in the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KeyType {
    /// A number.
    Float,
    /// A whole number.
    Integer,
    /// `true` or `false`.
    Bool,
    /// A string: a name.
    Name,
    /// One of these strings.
    Choice(&'static [&'static str]),
    /// Three numbers.
    Vec3,
    /// A node index or `"last"`.
    Node,
    /// Seconds or `"auto"`.
    TimeStep,
    /// A list of numbers.
    Floats,
    /// A list of names.
    Names,
    /// An inline table or a list of inline tables (declared under
    /// `table.key`).
    Table,
}

/// What an absent key means.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Absent {
    /// The key must be given.
    Required,
    /// Required in the situation named (as docs/scene.md says it).
    RequiredWhen(&'static str),
    /// Absent is the same as this TOML value (tested: a scene with it
    /// parses to the same scene as one without).
    Literal(&'static str),
    /// Absent means what this text says (nothing, or a derived value).
    Means(&'static str),
}

impl Absent {
    /// The text docs/scene.md's default column gives (backticks aside).
    pub fn doc_text(self) -> &'static str {
        match self {
            Absent::Required => "required",
            Absent::RequiredWhen(t) | Absent::Literal(t) | Absent::Means(t) => t,
        }
    }
}

/// The values a key accepts, checked before any work (tested: a value just
/// outside is refused with the key named).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Range {
    /// Any value of its type (or a rule too specific for this list).
    Any,
    /// A number > 0.
    Positive,
    /// A number ≥ 0.
    NonNegative,
    /// A number in the interval; `open` ends excluded.
    Interval {
        /// Lower end.
        low: f64,
        /// Whether `low` itself is refused.
        low_open: bool,
        /// Upper end.
        high: f64,
        /// Whether `high` itself is refused.
        high_open: bool,
    },
    /// A whole number in `min..=max`.
    Count {
        /// Smallest accepted.
        min: u64,
        /// Largest accepted.
        max: u64,
    },
}

/// One key of a scene file.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Key {
    /// Its table: `analysis`, `rod` (for `[[rod]]`), `wire.quadrature` (an
    /// inline table of `[wire]`), …
    pub table: &'static str,
    /// The key as written.
    pub name: &'static str,
    /// What it holds.
    pub ty: KeyType,
    /// Its unit (empty: none).
    pub unit: &'static str,
    /// What its absence means.
    pub default: Absent,
    /// The values accepted.
    pub range: Range,
    /// The Python arguments that take the same value, as
    /// `Class.method(argument)`.
    pub python: &'static [&'static str],
    /// One line: what it is.
    pub doc: &'static str,
}

const fn key(table: &'static str, name: &'static str, ty: KeyType) -> Key {
    Key {
        table,
        name,
        ty,
        unit: "",
        default: Absent::Means(""),
        range: Range::Any,
        python: &[],
        doc: "",
    }
}

impl Key {
    const fn unit(self, unit: &'static str) -> Key {
        Key { unit, ..self }
    }
    const fn default(self, default: Absent) -> Key {
        Key { default, ..self }
    }
    const fn required(self) -> Key {
        Key {
            default: Absent::Required,
            ..self
        }
    }
    const fn range(self, range: Range) -> Key {
        Key { range, ..self }
    }
    const fn python(self, python: &'static [&'static str]) -> Key {
        Key { python, ..self }
    }
    const fn doc(self, doc: &'static str) -> Key {
        Key { doc, ..self }
    }

    /// `table.name`, as the key's errors name it (a `[[table]]`'s with its
    /// index: `rod[0].radius`).
    pub fn path(&self) -> String {
        format!("{}.{}", self.table, self.name)
    }
}

/// A number in [low, high].
const fn closed(low: f64, high: f64) -> Range {
    Range::Interval {
        low,
        low_open: false,
        high,
        high_open: false,
    }
}

/// A number in (low, high].
const fn open_closed(low: f64, high: f64) -> Range {
    Range::Interval {
        low,
        low_open: true,
        high,
        high_open: false,
    }
}

/// A number in (low, high).
const fn open(low: f64, high: f64) -> Range {
    Range::Interval {
        low,
        low_open: true,
        high,
        high_open: true,
    }
}

/// A number in [low, high).
const fn closed_open(low: f64, high: f64) -> Range {
    Range::Interval {
        low,
        low_open: false,
        high,
        high_open: true,
    }
}

const fn count(min: u64, max: u64) -> Range {
    Range::Count { min, max }
}

use Absent::{Literal, Means, RequiredWhen};
use KeyType::*;
use Range::{NonNegative, Positive};

/// The restitution models' names.
pub const RESTITUTION_MODELS: &[&str] = &["exact", "flores", "lankarani-nikravesh"];

/// Every key of a scene file.
pub const KEYS: &[Key] = &[
    // [analysis]
    key("analysis", "kind", Choice(&["static", "dynamic"]))
        .required()
        .doc("what to solve"),
    key("analysis", "end_time", Float)
        .unit("s")
        .default(RequiredWhen("required (dynamic)"))
        .range(Positive)
        .python(&["Simulation.from_wire(end_time)"])
        .doc("simulated time"),
    key("analysis", "time_step", TimeStep)
        .unit("s")
        .default(RequiredWhen("required (dynamic)"))
        .python(&["Simulation.from_wire(time_step)"])
        .doc("generalized-α step h, or \"auto\" (adaptive steps)"),
    key("analysis", "error_tolerance", Float)
        .unit("m")
        .default(RequiredWhen("required with \"auto\""))
        .range(Positive)
        .python(&["Simulation.from_wire(error_tolerance)"])
        .doc("adaptive steps: the position error one step may add"),
    key("analysis", "max_time_step", Float)
        .unit("s")
        .default(Means("end_time / 100"))
        .range(Positive)
        .python(&["Simulation.from_wire(max_time_step)"])
        .doc("adaptive steps: the longest step"),
    key("analysis", "spectral_radius", Float)
        .default(Literal("0.9"))
        .range(closed(0.0, 1.0))
        .python(&["Simulation.from_wire(spectral_radius)"])
        .doc("generalized-α ρ∞"),
    key("analysis", "newton", Choice(&["modified", "full"]))
        .default(Literal("\"modified\""))
        .doc("modified or full Newton"),
    key("analysis", "broyden", Bool)
        .default(Literal("false"))
        .doc("Broyden's updates of the kept factorization"),
    key("analysis", "load_steps", Integer)
        .default(Literal("1"))
        .range(count(1, 1_000_000))
        .doc("static: equal load increments"),
    key("analysis", "tolerance", Float)
        .default(Literal("1e-10"))
        .range(open(0.0, 1.0))
        .doc("Newton's relative residual tolerance"),
    key("analysis", "max_iterations", Integer)
        .default(Means("50 static, 25 dynamic"))
        .doc("Newton iterations per load step / time step"),
    key("analysis", "initial", Choice(&["reference", "static"]))
        .default(Literal("\"reference\""))
        .doc("dynamic: start from the reference or the static equilibrium"),
    // [gravity]
    key("gravity", "acceleration", Vec3)
        .unit("m/s²")
        .python(&["Wire.gravity(acceleration)"])
        .doc("g"),
    // [[material]]
    key("material", "name", Name)
        .required()
        .doc("referenced by layers"),
    key(
        "material",
        "model",
        Choice(&["st-venant-kirchhoff", "mooney-rivlin", "elastic-plastic"]),
    )
    .required()
    .doc("the law"),
    key("material", "density", Float)
        .unit("kg/m³")
        .required()
        .range(Positive)
        .python(&[
            "Material.st_venant_kirchhoff(density)",
            "Material.mooney_rivlin(density)",
            "Material.elastic_plastic(density)",
        ])
        .doc("ρ"),
    key("material", "youngs_modulus", Float)
        .unit("Pa")
        .default(RequiredWhen("required (SVK, elastic-plastic)"))
        .range(Positive)
        .python(&[
            "Material.st_venant_kirchhoff(youngs_modulus)",
            "Material.elastic_plastic(youngs_modulus)",
        ])
        .doc("E"),
    key("material", "poisson_ratio", Float)
        .default(Means("0 (SVK, elastic-plastic)"))
        .range(open(-1.0, 0.5))
        .python(&[
            "Material.st_venant_kirchhoff(poisson_ratio)",
            "Material.elastic_plastic(poisson_ratio)",
        ])
        .doc("ν"),
    key("material", "bending_factor", Float)
        .default(Means("1 (SVK)"))
        .range(closed(0.0, 1.0))
        .python(&["Material.st_venant_kirchhoff(bending_factor)"])
        .doc("ω, the fraction of the continuum bending stiffness kept"),
    key("material", "mu10", Float)
        .unit("Pa")
        .default(RequiredWhen("required (Mooney–Rivlin)"))
        .range(NonNegative)
        .python(&["Material.mooney_rivlin(mu10)"])
        .doc("Mooney–Rivlin μ10"),
    key("material", "mu01", Float)
        .unit("Pa")
        .default(RequiredWhen("required (Mooney–Rivlin)"))
        .range(NonNegative)
        .python(&["Material.mooney_rivlin(mu01)"])
        .doc("Mooney–Rivlin μ01"),
    key("material", "penalty", Float)
        .default(RequiredWhen("required (Mooney–Rivlin)"))
        .range(Positive)
        .python(&["Material.mooney_rivlin(penalty)"])
        .doc("Mooney–Rivlin volume penalty κ"),
    key("material", "yield_stress", Float)
        .unit("Pa")
        .default(Means("none: not checked; required (elastic-plastic)"))
        .range(Positive)
        .python(&[
            "Material.st_venant_kirchhoff(yield_stress)",
            "Material.elastic_plastic(yield_stress)",
        ])
        .doc("f_y: a stress past it is warned of, members get their utilization"),
    key("material", "hardening_modulus", Float)
        .unit("Pa")
        .default(Means("0: perfectly plastic (elastic-plastic)"))
        .range(NonNegative)
        .python(&["Material.elastic_plastic(hardening_modulus)"])
        .doc("H, linear hardening of an elastic-plastic material"),
    key("material", "hardening", Choice(&["kinematic", "isotropic"]))
        .default(Literal("\"kinematic\""))
        .python(&["Material.elastic_plastic(hardening)"])
        .doc("how H acts: the yield surface translates or grows"),
    key("material", "rate", Table)
        .default(Means("none: rate-independent"))
        .doc("the rate law of an elastic-plastic material"),
    key("material.rate", "kind", Choice(&["cowper-symonds"]))
        .required()
        .doc("f_y (1 + (ε̇ / D)^(1/q))"),
    key("material.rate", "d", Float)
        .unit("1/s")
        .required()
        .range(Positive)
        .python(&["Material.elastic_plastic(rate_d)"])
        .doc("D (mild steel: 40.4)"),
    key("material.rate", "q", Float)
        .required()
        .range(Positive)
        .python(&["Material.elastic_plastic(rate_q)"])
        .doc("q (mild steel: 5)"),
    key("material", "locking", Choice(&["centerline", "none"]))
        .default(Literal("\"centerline\""))
        .doc("the locking remedy"),
    // [wire] (and the shared keys of [[beam]])
    key("wire", "length", Float)
        .unit("m")
        .required()
        .range(Positive)
        .python(&["Wire(length)", "Wire.member(length)"])
        .doc("reference (unstretched) length"),
    key("wire", "elements", Integer)
        .default(RequiredWhen("required (or `segments`)"))
        .range(count(1, crate::model::MAX_ELEMENTS as u64))
        .python(&["Wire(elements)", "Wire.member(elements)"])
        .doc("equal elements over the length"),
    key("wire", "segments", Table)
        .unit("m")
        .python(&["Wire.graded(segments)"])
        .doc("a graded mesh: regions from node 0 on"),
    key("wire", "origin", Vec3)
        .unit("m")
        .default(Literal("[0, 0, 0]"))
        .python(&["Wire.placed(origin)", "Wire.member(origin)"])
        .doc("position of node 0"),
    key("wire", "direction", Vec3)
        .default(Literal("[1, 0, 0]"))
        .python(&["Wire.placed(direction)", "Wire.member(direction)"])
        .doc("the wire's axis (normalised)"),
    key("wire", "layers", Table)
        .unit("m")
        .python(&["Wire.layer(outer_radius)", "Wire.member(layers)"])
        .doc("concentric layers from the centre out"),
    key("wire", "rectangle", Table)
        .unit("m")
        .doc("a rectangular section instead of layers"),
    key("wire", "damping", Table)
        .default(Means("[damping]'s"))
        .doc("this beam's own structural damping"),
    key("wire", "quadrature", Table)
        .default(Means("{ axial = 3, section = 3 }"))
        .doc("quadrature orders"),
    key("wire.layers", "material", Name)
        .required()
        .doc("the layer's material"),
    key("wire.layers", "outer_radius", Float)
        .unit("m")
        .required()
        .range(Positive)
        .doc("its outer radius"),
    key("wire.layers", "inner_radius", Float)
        .unit("m")
        .default(Literal("0"))
        .range(NonNegative)
        .python(&["Wire.bore(inner_radius)", "Wire.member(inner_radius)"])
        .doc("first layer only: a hollow section"),
    key("wire.rectangle", "material", Name)
        .required()
        .doc("the section's material"),
    key("wire.rectangle", "width", Float)
        .unit("m")
        .required()
        .range(Positive)
        .doc("along y"),
    key("wire.rectangle", "height", Float)
        .unit("m")
        .required()
        .range(Positive)
        .doc("along z"),
    key("wire.quadrature", "axial", Integer)
        .default(Literal("3"))
        .doc("Gauss points along the element"),
    key("wire.quadrature", "section", Integer)
        .default(Literal("3"))
        .doc("ring-rule order per layer"),
    key("wire.segments", "length", Float)
        .unit("m")
        .required()
        .range(Positive)
        .doc("the region's reference length"),
    key("wire.segments", "elements", Integer)
        .required()
        .range(count(1, crate::model::MAX_ELEMENTS as u64))
        .doc("equal elements in it"),
    // [[beam]]: the keys of [wire] and these
    key("beam", "name", Name)
        .required()
        .python(&["Wire.member(name)"])
        .doc("unique, not \"wire\""),
    key("beam", "contact_law", Choice(&["hertz", "line"]))
        .default(Literal("\"hertz\""))
        .python(&["Wire.member(contact_law)"])
        .doc("how the wire touches the member"),
    key("beam", "contact_stiffness", Float)
        .unit("N/m²")
        .default(RequiredWhen("required with contact_law = \"line\""))
        .range(Positive)
        .python(&["Wire.member(contact_stiffness)"])
        .doc("ε_L under the line law"),
    key("beam", "friction", Float)
        .default(Literal("0"))
        .range(NonNegative)
        .python(&["Wire.member(friction)"])
        .doc("Coulomb μ between wire and member"),
    key("beam", "restitution", Float)
        .default(Means("elastic"))
        .range(open_closed(0.0, 1.0))
        .python(&["Wire.member(restitution)"])
        .doc("coefficient of restitution e"),
    key("beam", "restitution_model", Choice(RESTITUTION_MODELS))
        .default(Literal("\"exact\""))
        .python(&["Wire.member(restitution_model)"])
        .doc("how the damping follows from e"),
    // [[support]]
    key("support", "node", Node)
        .required()
        .python(&["Wire.support(node)", "Wire.spring(node)"])
        .doc("node index (on its beam) or \"last\""),
    key("support", "beam", Name)
        .default(Means("the wire"))
        .python(&["Wire.support(beam)", "Wire.spring(beam)"])
        .doc("the [[beam]] it holds"),
    key(
        "support",
        "kind",
        Choice(&["clamp", "fixed", "pin", "hinge", "spring"]),
    )
    .required()
    .python(&["Wire.support(kind)"])
    .doc("how it is held"),
    key("support", "stiffness", Vec3)
        .unit("N/m")
        .default(RequiredWhen("required (spring)"))
        .python(&["Wire.spring(stiffness)"])
        .doc("translational stiffness along x, y, z"),
    key("support", "rotational_stiffness", Float)
        .unit("N m/rad")
        .default(Literal("0"))
        .range(NonNegative)
        .python(&["Wire.spring(rotational_stiffness)"])
        .doc("bending spring on the node's unit tangent"),
    key("support", "torsional_stiffness", Float)
        .unit("N m/rad")
        .default(Literal("0"))
        .range(NonNegative)
        .python(&["Wire.spring(torsional_stiffness)"])
        .doc("torsional spring on the section's twist"),
    key("support", "damping", Float)
        .unit("N s/m")
        .default(Literal("0"))
        .range(NonNegative)
        .python(&["Wire.spring(damping)"])
        .doc("dashpot on the node's velocity"),
    key("support", "position", Vec3)
        .unit("m")
        .default(Means("its reference position"))
        .doc("where the node is held"),
    key("support", "release_time", Float)
        .unit("s")
        .default(Means("never"))
        .range(NonNegative)
        .doc("when the support lets go"),
    // [[load]]
    key("load", "node", Node)
        .required()
        .python(&["Wire.load(node)"])
        .doc("on its beam"),
    key("load", "beam", Name)
        .default(Means("the wire"))
        .python(&["Wire.load(beam)"])
        .doc("the [[beam]] it loads"),
    key("load", "force", Vec3)
        .unit("N")
        .python(&["Wire.load(force)"])
        .doc("constant force at the node"),
    key("load", "moment", Vec3)
        .unit("N m")
        .doc("constant moment at the node, of fixed direction in space however far the node turns"),
    key("load", "follower", Bool)
        .default(Literal("false"))
        .doc("the moment turns with the node"),
    // [[rod]]
    key("rod", "center", Vec3)
        .unit("m")
        .required()
        .python(&["Wire.rod(center)"])
        .doc("a point on the rod axis"),
    key("rod", "axis", Vec3)
        .required()
        .python(&["Wire.rod(axis)"])
        .doc("axis direction (normalised)"),
    key("rod", "radius", Float)
        .unit("m")
        .required()
        .range(Positive)
        .python(&["Wire.rod(radius)"])
        .doc("its radius"),
    key("rod", "length", Float)
        .unit("m")
        .default(Means("infinite"))
        .range(Positive)
        .python(&["Wire.rod(length)"])
        .doc("finite rod centred on `center`"),
    // "line" is the law of a rod that names none, yet such a rod must name
    // its law to give a stiffness: the default is never the same scene.
    key("rod", "contact_law", Choice(&["line", "hertz", "surface"]))
        .default(Means("\"line\""))
        .doc("how the contact force is computed"),
    key("rod", "contact_stiffness", Float)
        .unit("N/m² (line), N/m³ (surface)")
        .default(RequiredWhen(
            "required for line and surface; refused for hertz",
        ))
        .range(Positive)
        .python(&["Wire.rod(stiffness)"])
        .doc("ε_L (line) or ε_N (surface)"),
    key("rod", "material", Name)
        .default(RequiredWhen("required for hertz; optional otherwise"))
        .doc("the rod's material"),
    key("rod", "friction", Float)
        .default(Literal("0"))
        .range(NonNegative)
        .python(&["Wire.rod(friction)"])
        .doc("Coulomb μ"),
    key("rod", "restitution", Float)
        .default(Means("absent: no damping"))
        .range(open_closed(0.0, 1.0))
        .python(&["Wire.rod(restitution)"])
        .doc("coefficient of restitution e of contact damping"),
    key("rod", "restitution_model", Choice(RESTITUTION_MODELS))
        .default(Literal("\"exact\""))
        .python(&["Wire.rod(restitution_model)"])
        .doc("how the damping follows from e"),
    // [[ground]]
    key("ground", "point", Vec3)
        .unit("m")
        .required()
        .python(&["Wire.ground(point)"])
        .doc("a point of the plane"),
    key("ground", "normal", Vec3)
        .required()
        .python(&["Wire.ground(normal)"])
        .doc("its normal, towards the side the wire belongs on (normalised)"),
    key("ground", "contact_stiffness", Float)
        .unit("N/m²")
        .required()
        .range(Positive)
        .python(&["Wire.ground(stiffness)"])
        .doc("ε_L, the line law's force per length per penetration"),
    key("ground", "friction", Float)
        .default(Literal("0"))
        .range(NonNegative)
        .python(&["Wire.ground(friction)"])
        .doc("Coulomb μ"),
    key("ground", "restitution", Float)
        .default(Means("absent: no damping"))
        .range(open_closed(0.0, 1.0))
        .python(&["Wire.ground(restitution)"])
        .doc("coefficient of restitution e of contact damping"),
    key("ground", "restitution_model", Choice(RESTITUTION_MODELS))
        .default(Literal("\"exact\""))
        .python(&["Wire.ground(restitution_model)"])
        .doc("how the damping follows from e"),
    key("ground", "beams", Names)
        .default(Literal("[\"wire\"]"))
        .python(&["Wire.ground(beams)"])
        .doc("the beams that touch it: the wire and the frame members named"),
    // [contact]
    key("contact", "zone_points", Integer)
        .default(Literal("8"))
        .range(count(1, 32))
        .doc("line laws: Gauss points per active zone"),
    key("contact", "stations", Integer)
        .default(Literal("8"))
        .range(count(1, 64))
        .doc("surface law: Gauss stations per element"),
    key("contact", "angles", Integer)
        .default(Literal("16"))
        .range(count(3, 256))
        .doc("surface law: test points around the outer surface"),
    key("contact", "slip_velocity", Float)
        .unit("m/s")
        .default(Literal("1e-3"))
        .range(Positive)
        .doc("regularization velocity of Coulomb friction"),
    key("contact", "max_penetration", Float)
        .unit("wire radii")
        .default(Literal("1"))
        .range(Positive)
        .doc("a step penetrating deeper is rejected and halved"),
    key("contact", "min_impact_speed", Float)
        .unit("m/s")
        .default(Literal("0.1"))
        .range(Positive)
        .doc("contact damping: the smallest approach speed its factor uses"),
    // [damping] (and a beam's own `damping = { … }`)
    key("damping", "kind", Choice(&["kelvin-voigt", "rayleigh"]))
        .required()
        .doc("the damping law"),
    key("damping", "strain_rate_coefficient", Float)
        .unit("s")
        .range(Positive)
        .python(&["Wire.kelvin_voigt(coefficient)"])
        .doc("Kelvin–Voigt c"),
    key("damping", "mass", Float)
        .unit("1/s")
        .range(NonNegative)
        .python(&["Wire.rayleigh(mass)"])
        .doc("Rayleigh mass factor"),
    key("damping", "stiffness", Float)
        .unit("s")
        .range(NonNegative)
        .python(&["Wire.rayleigh(stiffness)"])
        .doc("Rayleigh stiffness factor"),
    // [[clearance]]
    key(
        "clearance",
        "kind",
        Choice(&["box", "half-space", "ground"]),
    )
    .required()
    .doc("the zone's shape"),
    key("clearance", "min", Vec3)
        .unit("m")
        .doc("box: its corner of least x, y, z"),
    key("clearance", "max", Vec3)
        .unit("m")
        .doc("box: its corner of largest x, y, z"),
    key("clearance", "point", Vec3)
        .unit("m")
        .doc("half-space: a point of its plane"),
    key("clearance", "normal", Vec3).doc("half-space: the normal, out of the zone"),
    key("clearance", "ground", Integer)
        .doc("ground: the [[ground]]'s index, its plane the zone's surface"),
    // [output]
    key("output", "every", Integer)
        .default(Literal("1"))
        .range(count(1, u64::MAX))
        .doc("write every N-th step"),
    key("output", "checkpoint_every", Integer)
        .default(Literal("1000"))
        .doc("checkpoint every N steps (0: never)"),
    key("output", "vtk", Bool)
        .default(Literal("true"))
        .doc("write ParaView files"),
    key("output", "vtk_every", Integer)
        .default(Means("at most 50 frames"))
        .doc("a ParaView frame every N steps"),
    key("output", "plots", Bool)
        .default(Literal("true"))
        .doc("write PNG plots"),
    key("output", "cfc", Float)
        .unit("Hz")
        .default(Literal("60"))
        .range(Positive)
        .doc("channel frequency class of the filtered contact forces"),
    key("output", "response_frequencies", Floats)
        .unit("Hz")
        .default(Means("none"))
        .doc("frequencies of the oscillators the supports' forces drive"),
    key("output", "response_damping", Float)
        .default(Literal("0.02"))
        .range(closed_open(0.0, 1.0))
        .doc("their damping ratio ζ"),
];

/// The keys of `table`, in declaration order.
pub fn keys_of(table: &str) -> impl Iterator<Item = &'static Key> + '_ {
    KEYS.iter().filter(move |k| k.table == table)
}

/// The declaration of `table.name`, if there is one.
pub fn find(table: &str, name: &str) -> Option<&'static Key> {
    KEYS.iter().find(|k| k.table == table && k.name == name)
}
