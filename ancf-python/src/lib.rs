//! `ancf._ancf`: the Python face of ancf-core. Scenes are read
//! and validated exactly as by the CLI; a `Simulation` wraps the core's
//! `Simulation`; results come back as NumPy arrays. Every error is a Python
//! exception (a Rust panic becomes `pyo3_runtime.PanicException`).

use ancf_core::model::damping::Damping;
use ancf_core::scene::{Analysis, Scene as CoreScene, SceneError as CoreSceneError};
use ancf_core::solve::dynamics::StepControl;
use ancf_core::solve::simulation::{
    Initial, Simulation as CoreSimulation, SimulationError as CoreSimError,
};
use ancf_output::run::observations::Observations;
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{
    PyFileNotFoundError, PyOSError, PyPermissionError, PyRuntimeError, PyValueError,
};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

create_exception!(
    ancf,
    SceneError,
    PyValueError,
    "A scene that cannot be run: `.field` names the field at fault (e.g. \"wire.elements\"); `.line` and `.column` locate an error of TOML syntax or type (else None)."
);
create_exception!(
    ancf,
    PlausibilityWarning,
    pyo3::exceptions::PyUserWarning,
    "What a scene will likely do badly, or what a run did that its numbers cannot show: a unit slip (E = 2e5 Pa), a contact the time step does not resolve, a stress past yield. Raised when a scene or a wire is built and when a run reaches its end; `warnings.simplefilter(\"error\")` makes it an exception."
);
create_exception!(
    ancf,
    SimulationError,
    PyRuntimeError,
    "A simulation that could not go on: the message names the step, the time and the likely cause."
);

/// A count or an index from Python: a whole number ≥ 0. Anything else is
/// refused in the user's words ("must be a whole number, got -4"; Python
/// adds which argument) instead of the conversion's ("can't convert
/// negative int to unsigned"); the range a count needs is the core's check.
#[derive(Clone, Copy, Debug)]
struct Whole(usize);

impl<'a, 'py> FromPyObject<'a, 'py> for Whole {
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let shown = || obj.repr().map_or_else(|_| "?".into(), |r| r.to_string());
        if obj.is_instance_of::<PyBool>() || !obj.is_instance_of::<PyInt>() {
            return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "must be a whole number, got {}",
                shown()
            )));
        }
        obj.extract::<usize>().map(Whole).map_err(|_| {
            PyValueError::new_err(format!("must be a whole number ≥ 0, got {}", shown()))
        })
    }
}

/// Each of `warnings` as a Python `PlausibilityWarning` at the caller's
/// line; an error where the warnings filter turns them into exceptions.
fn warn_all(py: Python<'_>, warnings: &[String]) -> PyResult<()> {
    let category = py.get_type::<PlausibilityWarning>();
    for w in warnings {
        let text = std::ffi::CString::new(w.replace('\0', " ")).expect("NUL bytes replaced");
        PyErr::warn(py, category.as_any(), &text, 1)?;
    }
    Ok(())
}

fn scene_error(py: Python<'_>, e: &CoreSceneError) -> PyErr {
    let err = SceneError::new_err(e.to_string());
    let value = err.value(py);
    let _ = value.setattr("field", e.field.clone());
    let (line, column) = location(&e.message).unzip();
    let _ = value.setattr("line", line);
    let _ = value.setattr("column", column);
    err
}

/// Line and column (from 1) of a TOML error, from toml's "at line N,
/// column M".
fn location(message: &str) -> Option<(usize, usize)> {
    let rest = &message[message.find("at line ")? + "at line ".len()..];
    let (line, rest) = rest.split_once(", column ")?;
    let column: String = rest.chars().take_while(char::is_ascii_digit).collect();
    Some((line.parse().ok()?, column.parse().ok()?))
}

/// How deep a scene dict may nest: a scene's own nesting is four levels
/// (`wire.layers[0].material`); deeper is a mistake, or a dict that holds
/// itself, which would otherwise recurse until the interpreter's stack ends.
const MAX_NESTING: usize = 32;

/// A Python value as TOML, for `Scene.from_dict`; `path` names the key for
/// errors, `depth` how deep the value sits.
fn to_toml(
    value: &Bound<'_, PyAny>,
    path: &str,
    depth: usize,
) -> Result<toml::Value, CoreSceneError> {
    let bad = |what: String| CoreSceneError {
        field: path.to_string(),
        message: what,
    };
    if depth > MAX_NESTING {
        return Err(bad(format!(
            "nested deeper than {MAX_NESTING} levels (a dict or list that contains itself?)"
        )));
    }
    if let Ok(d) = value.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in d.iter() {
            let key: String = k.extract().map_err(|_| {
                bad(format!(
                    "keys must be strings, got {}",
                    k.get_type()
                        .name()
                        .map(|n| n.to_string())
                        .unwrap_or_default()
                ))
            })?;
            let sub = if path.is_empty() {
                key.clone()
            } else {
                format!("{path}.{key}")
            };
            table.insert(key, to_toml(&v, &sub, depth + 1)?);
        }
        Ok(toml::Value::Table(table))
    } else if value.is_instance_of::<PyBool>() {
        Ok(toml::Value::Boolean(value.extract().unwrap_or(false)))
    } else if value.is_instance_of::<PyInt>() {
        value
            .extract::<i64>()
            .map(toml::Value::Integer)
            .map_err(|_| bad("integer out of range".into()))
    } else if value.is_instance_of::<PyFloat>() {
        Ok(toml::Value::Float(value.extract().unwrap_or(f64::NAN)))
    } else if value.is_instance_of::<PyString>() {
        Ok(toml::Value::String(value.extract().unwrap_or_default()))
    } else if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (i, v) in value
            .try_iter()
            .map_err(|_| bad("not iterable".into()))?
            .enumerate()
        {
            let v = v.map_err(|_| bad("not iterable".into()))?;
            items.push(to_toml(&v, &format!("{path}[{i}]"), depth + 1)?);
        }
        Ok(toml::Value::Array(items))
    } else {
        let name = value
            .get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_default();
        Err(bad(format!(
            "unsupported type {name} (use dict, list, str, int, float, bool)"
        )))
    }
}

/// A validated scene (the same schema and validation as `ancf check`).
#[pyclass(module = "ancf", frozen)]
pub struct Scene {
    inner: CoreScene,
}

#[pymethods]
impl Scene {
    /// Reads and validates a scene file (TOML). Raises `SceneError`.
    #[staticmethod]
    fn from_file(py: Python<'_>, path: std::path::PathBuf) -> PyResult<Scene> {
        // A file that cannot be read is an OSError (FileNotFoundError,
        // PermissionError, …), as Python's own open() raises.
        let text = std::fs::read_to_string(&path).map_err(|e| {
            let name = path.display().to_string();
            let (code, what) = (e.raw_os_error().unwrap_or(0), e.to_string());
            match e.kind() {
                std::io::ErrorKind::NotFound => PyFileNotFoundError::new_err((code, what, name)),
                std::io::ErrorKind::PermissionDenied => {
                    PyPermissionError::new_err((code, what, name))
                }
                _ => PyOSError::new_err((code, what, name)),
            }
        })?;
        Self::from_toml(py, &text)
    }

    /// Validates a scene given as TOML text. Raises `SceneError`.
    #[staticmethod]
    fn from_toml(py: Python<'_>, text: &str) -> PyResult<Scene> {
        let inner = CoreScene::from_toml(text).map_err(|e| scene_error(py, &e))?;
        warn_all(py, &inner.warnings())?;
        Ok(Scene { inner })
    }

    /// Validates a scene given as nested dicts and lists with the scene
    /// file's keys (`{"wire": {"length": 2.0, ...}, "rod": [{...}], ...}`).
    #[staticmethod]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyDict>) -> PyResult<Scene> {
        let value = to_toml(d.as_any(), "", 0).map_err(|e| scene_error(py, &e))?;
        let text = toml::to_string(&value).map_err(|e| {
            scene_error(
                py,
                &CoreSceneError {
                    field: String::new(),
                    message: e.to_string(),
                },
            )
        })?;
        // A line of the text generated here means nothing to the caller:
        // the field names the place.
        Self::from_toml(py, &text).inspect_err(|e| {
            let _ = e.value(py).setattr("line", py.None());
            let _ = e.value(py).setattr("column", py.None());
        })
    }

    /// Number of elements.
    #[getter]
    fn elements(&self) -> usize {
        self.inner.model.element_count()
    }

    /// Unknowns of the model (coordinates not fixed by supports).
    #[getter]
    fn unknowns(&self) -> usize {
        self.inner.model.n_unknowns
    }

    /// "static" or "dynamic".
    #[getter]
    fn kind(&self) -> &'static str {
        match self.inner.analysis {
            Analysis::Static { .. } => "static",
            Analysis::Dynamic { .. } => "dynamic",
        }
    }

    /// The TOML text the scene was read from.
    #[getter]
    fn source(&self) -> &str {
        &self.inner.source
    }

    /// What the scene will likely do badly, said before it runs: each rod
    /// whose line-law contact the time step does not resolve, with the
    /// step that would (the CLI prints these as warnings).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings()
    }

    fn __repr__(&self) -> String {
        format!(
            "ancf.Scene({} analysis, {} elements, {} unknowns)",
            self.kind(),
            self.elements(),
            self.unknowns()
        )
    }
}

/// A layer material (SI units).
#[pyclass(module = "ancf", frozen)]
#[derive(Clone)]
pub struct Material {
    inner: ancf_core::material::Material,
}

#[pymethods]
impl Material {
    /// St. Venant–Kirchhoff: density (kg/m³), Young's modulus (Pa),
    /// Poisson's ratio, weakened-bending coefficient ω (1: plain continuum),
    /// and the yield stress f_y (Pa) the run checks stresses against (the
    /// law stays elastic; None: not checked).
    #[staticmethod]
    #[pyo3(signature = (density, youngs_modulus, poisson_ratio=None, bending_factor=None, yield_stress=None))]
    fn st_venant_kirchhoff(
        density: f64,
        youngs_modulus: f64,
        poisson_ratio: Option<f64>,
        bending_factor: Option<f64>,
        yield_stress: Option<f64>,
    ) -> PyResult<Material> {
        use ancf_core::material::{DEFAULT_BENDING_FACTOR, DEFAULT_POISSON_RATIO};
        let inner = ancf_core::material::Material {
            yield_stress,
            ..ancf_core::material::Material::st_venant_kirchhoff(
                density,
                youngs_modulus,
                poisson_ratio.unwrap_or(DEFAULT_POISSON_RATIO),
                bending_factor.unwrap_or(DEFAULT_BENDING_FACTOR),
            )
        };
        inner
            .check()
            .map_err(|e| value_error(&e.field, &e.message))?;
        Ok(Material { inner })
    }

    /// Elastic–plastic (beam-type J2 in the beam stresses): density
    /// (kg/m³), Young's modulus (Pa), yield stress f_y (Pa), Poisson's
    /// ratio, linear hardening modulus H (Pa, default 0: perfectly
    /// plastic), `hardening` "kinematic" (default) or "isotropic", and the
    /// Cowper–Symonds rate law's D (1/s) and q, both or neither.
    #[staticmethod]
    #[pyo3(signature = (density, youngs_modulus, yield_stress, poisson_ratio=None, hardening_modulus=None, hardening=None, rate_d=None, rate_q=None))]
    #[allow(clippy::too_many_arguments)]
    fn elastic_plastic(
        density: f64,
        youngs_modulus: f64,
        yield_stress: f64,
        poisson_ratio: Option<f64>,
        hardening_modulus: Option<f64>,
        hardening: Option<String>,
        rate_d: Option<f64>,
        rate_q: Option<f64>,
    ) -> PyResult<Material> {
        use ancf_core::material::beam_plasticity::{CowperSymonds, Hardening};
        let hardening = Hardening::from_name(hardening.as_deref())
            .map_err(|message| value_error("hardening", &message))?;
        let rate = match (rate_d, rate_q) {
            (None, None) => None,
            (Some(d), Some(q)) => Some(CowperSymonds { d, q }),
            (None, Some(_)) => return Err(value_error("rate_d", "needed with rate_q")),
            (Some(_), None) => return Err(value_error("rate_q", "needed with rate_d")),
        };
        let inner = ancf_core::material::Material {
            model: ancf_core::material::MaterialModel::ElasticPlastic {
                youngs_modulus,
                poisson_ratio: poisson_ratio.unwrap_or(ancf_core::material::DEFAULT_POISSON_RATIO),
                hardening_modulus: hardening_modulus.unwrap_or(0.0),
                hardening,
                rate,
            },
            ..ancf_core::material::Material::elastic_plastic(
                density,
                youngs_modulus,
                0.0,
                yield_stress,
                0.0,
            )
        };
        inner.check().map_err(|e| {
            let field = match e.field.as_str() {
                "rate.d" => "rate_d",
                "rate.q" => "rate_q",
                other => other,
            };
            value_error(field, &e.message)
        })?;
        Ok(Material { inner })
    }

    /// Nearly incompressible Mooney–Rivlin: density (kg/m³), μ10, μ01 (Pa),
    /// volume penalty κ (1e3 – 1e7; required, as in a scene).
    #[staticmethod]
    #[pyo3(signature = (density, mu10, mu01, penalty))]
    fn mooney_rivlin(density: f64, mu10: f64, mu01: f64, penalty: f64) -> PyResult<Material> {
        let inner = ancf_core::material::Material::mooney_rivlin(density, mu10, mu01, penalty);
        inner
            .check()
            .map_err(|e| value_error(&e.field, &e.message))?;
        Ok(Material { inner })
    }
}

/// A `ValueError` naming the argument: "`name`: `message`".
fn value_error(name: &str, message: &str) -> PyErr {
    PyValueError::new_err(format!("{name}: {message}"))
}

/// `from_wire`'s step arguments as the integrator takes them: the first
/// (or only) step h (s) and, for `time_step="auto"`, the step control.
/// Arguments that do not fit together are refused by name; the values
/// themselves are checked with the other settings.
fn stepping(
    time_step: &Bound<'_, PyAny>,
    end_time: f64,
    error_tolerance: Option<f64>,
    max_time_step: Option<f64>,
) -> PyResult<(f64, Option<StepControl>)> {
    let fixed = match time_step.extract::<String>() {
        Ok(text) if text == "auto" => None,
        Ok(text) => {
            return Err(value_error(
                "time_step",
                &format!("seconds or \"auto\", got \"{text}\""),
            ));
        }
        Err(_) => Some(
            time_step
                .extract::<f64>()
                .map_err(|_| value_error("time_step", "seconds or \"auto\""))?,
        ),
    };
    StepControl::from_keys(fixed, end_time, error_tolerance, max_time_step)
        .map_err(|e| value_error(&e.field, &e.message))
}

/// The name of a rod parameter as `Wire.rod` spells it.
fn rod_argument(field: &str) -> &str {
    match field {
        "contact_stiffness" => "stiffness",
        other => other,
    }
}

/// A finite number > 0, by the core's rule, named as the caller spells it.
fn positive(name: &str, v: f64) -> PyResult<f64> {
    ancf_core::check::positive("value", v).map_err(|e| value_error(name, &e.message))
}

fn vec3(name: &str, v: Vec<f64>) -> PyResult<[f64; 3]> {
    match v.as_slice() {
        [x, y, z] if v.iter().all(|c| c.is_finite()) => Ok([*x, *y, *z]),
        _ => Err(PyValueError::new_err(format!(
            "{name}: must be 3 finite numbers, got {v:?}"
        ))),
    }
}

/// The Wire builder's name for the part a model error is about: `length`,
/// `layers`, `layer 1`, `segments[0].elements`, `supports[2].node`, …
fn builder_field(e: &ancf_core::model::ModelError) -> String {
    use ancf_core::model::ModelError;
    match e {
        ModelError::Wire { what, .. } => what.clone(),
        ModelError::Layer { index, field, .. } => format!("layers[{index}].{field}"),
        ModelError::Segment { index, what, .. } => format!("segments[{index}].{what}"),
        ModelError::Support { index, what, .. } => format!("supports[{index}].{what}"),
        ModelError::NothingToSolve => "supports".into(),
        ModelError::Load { index, what, .. } => format!("loads[{index}].{what}"),
        ModelError::Gravity { field, .. } => field.clone(),
        ModelError::Rod { index, field, .. } => format!("rods[{index}].{}", rod_argument(field)),
        ModelError::Ground { index, field, .. } => {
            format!("grounds[{index}].{}", rod_argument(field))
        }
        ModelError::Contact { field, .. } => format!("contact.{field}"),
        ModelError::Damping { field, .. } => format!("damping.{field}"),
        ModelError::Member { index, error, .. } => {
            format!("members[{index}].{}", builder_field(error))
        }
    }
}

/// A wire described in code (no scene file): each method returns a new
/// `Wire`, so calls chain. Units: m, N, m/s².
#[pyclass(module = "ancf", frozen)]
#[derive(Clone)]
pub struct Wire {
    builder: ancf_core::model::WireBuilder,
}

#[pymethods]
impl Wire {
    /// A straight wire of `length` (m) in `elements` elements, along x from the origin.
    #[new]
    fn new(length: f64, elements: Whole) -> PyResult<Wire> {
        let elements = elements.0;
        positive("length", length)?;
        Ok(Wire {
            builder: ancf_core::model::WireBuilder::new(length, elements),
        })
    }

    /// A graded mesh: the wire becomes the `segments`, (length in m,
    /// elements) pairs in order from node 0 — fine where it meets a rod,
    /// coarse elsewhere. Replaces the length and element count given to `Wire`.
    fn graded(&self, segments: Vec<(f64, Whole)>) -> PyResult<Wire> {
        let segments: Vec<(f64, usize)> = segments.into_iter().map(|(l, n)| (l, n.0)).collect();
        if segments.is_empty() {
            return Err(PyValueError::new_err(
                "segments: give at least one (length, elements) pair",
            ));
        }
        let mut list = Vec::new();
        for (i, (length, elements)) in segments.into_iter().enumerate() {
            positive(&format!("segments[{i}].length"), length)?;
            if elements == 0 {
                return Err(PyValueError::new_err(format!(
                    "segments[{i}].elements: must be at least 1"
                )));
            }
            list.push(ancf_core::model::Segment { length, elements });
        }
        Ok(Wire {
            builder: self.builder.clone().graded(&list),
        })
    }

    /// Where the wire starts (m) and its direction.
    fn placed(&self, origin: Vec<f64>, direction: Vec<f64>) -> PyResult<Wire> {
        let b = self
            .builder
            .clone()
            .placed(vec3("origin", origin)?, vec3("direction", direction)?);
        Ok(Wire { builder: b })
    }

    /// The next concentric layer outward, up to `outer_radius` (m).
    fn layer(&self, material: &Material, outer_radius: f64) -> PyResult<Wire> {
        positive("outer_radius", outer_radius)?;
        Ok(Wire {
            builder: self
                .builder
                .clone()
                .layer(material.inner.clone(), outer_radius),
        })
    }

    /// A hollow section: the first layer starts at `inner_radius` (m), a tube.
    fn bore(&self, inner_radius: f64) -> Wire {
        Wire {
            builder: self.builder.clone().bore(inner_radius),
        }
    }

    /// A frame member `name`: a beam of the same element, `length` (m) in
    /// `elements` elements from `origin` along `direction`, its section
    /// the `layers` [(material, outer_radius), …] from `inner_radius` (m;
    /// 0: solid) out. Hold and load it with `beam=name`. The wire touches
    /// it by the line law against its deformed centerline: ε_L from the
    /// two outer materials (`contact_law="hertz"`, the default) or
    /// `contact_stiffness` (N/m², with `contact_law="line"`), Coulomb
    /// `friction`, contact damping by `restitution` (None: elastic) with
    /// its `restitution_model`; the keys' rules are the scene's.
    #[pyo3(signature = (name, length, elements, origin, direction, layers, inner_radius = 0.0, contact_stiffness = None, friction = 0.0, restitution = None, restitution_model = None, contact_law = None))]
    #[allow(clippy::too_many_arguments)]
    fn member(
        &self,
        name: &str,
        length: f64,
        elements: Whole,
        origin: Vec<f64>,
        direction: Vec<f64>,
        layers: Vec<(PyRef<'_, Material>, f64)>,
        inner_radius: f64,
        contact_stiffness: Option<f64>,
        friction: f64,
        restitution: Option<f64>,
        restitution_model: Option<&str>,
        contact_law: Option<&str>,
    ) -> PyResult<Wire> {
        let elements = elements.0;
        let damping = (restitution, restitution_model);
        let contact = ancf_core::model::contact::BeamContact::from_keys(
            contact_law,
            contact_stiffness,
            Some(friction),
            damping,
        )
        .map_err(|e| value_error(&e.field, &e.message))?;
        let mut beam = ancf_core::model::BeamBuilder::new(name, length, elements)
            .placed(vec3("origin", origin)?, vec3("direction", direction)?)
            .bore(inner_radius)
            .contact(contact);
        for (material, outer_radius) in layers {
            beam = beam.layer(material.inner.clone(), outer_radius);
        }
        Ok(Wire {
            builder: self.builder.clone().member(beam),
        })
    }

    /// A support at `node`: kind "pin" (position), "hinge" (position and
    /// the section's y gradient: turns about y only), "clamp" or "fixed"; on
    /// the member named `beam` (default: the wire).
    #[pyo3(signature = (node, kind, beam = None))]
    fn support(&self, node: Whole, kind: &str, beam: Option<&str>) -> PyResult<Wire> {
        let node = node.0;
        use ancf_core::model::SupportKind;
        let kind = match kind {
            "pin" => SupportKind::Pin,
            "hinge" => SupportKind::Hinge,
            "clamp" => SupportKind::Clamp,
            "fixed" => SupportKind::Fixed,
            other => {
                return Err(PyValueError::new_err(format!(
                    "kind: unknown support \"{other}\" (pin, hinge, clamp, fixed)"
                )));
            }
        };
        let support = ancf_core::model::Support::new(node, kind);
        let builder = self.builder.clone();
        Ok(Wire {
            builder: match beam {
                Some(beam) => builder.support_on(beam, support),
                None => builder.support_with(support),
            },
        })
    }

    /// An elastic support at `node` (of the member named `beam`; default:
    /// the wire): springs `stiffness` [kx, ky, kz] (N/m),
    /// `rotational_stiffness` (bending, N m/rad) and `torsional_stiffness`
    /// (twist, N m/rad), a dashpot `damping` (N s/m), relaxed where the
    /// node starts (a post or a clamp).
    #[pyo3(signature = (node, stiffness, rotational_stiffness = 0.0, damping = 0.0, torsional_stiffness = 0.0, beam = None))]
    fn spring(
        &self,
        node: Whole,
        stiffness: Vec<f64>,
        rotational_stiffness: f64,
        damping: f64,
        torsional_stiffness: f64,
        beam: Option<&str>,
    ) -> PyResult<Wire> {
        let node = node.0;
        use ancf_core::model::{Support, SupportKind};
        let spring = ancf_core::model::spring::Spring {
            stiffness: vec3("stiffness", stiffness)?,
            rotational_stiffness,
            torsional_stiffness,
            damping,
        };
        let support = Support::new(node, SupportKind::Spring(spring));
        Ok(Wire {
            builder: match beam {
                Some(beam) => self.builder.clone().support_on(beam, support),
                None => self.builder.clone().support_with(support),
            },
        })
    }

    /// Kelvin–Voigt damping (a scene's `[damping] kind = "kelvin-voigt"`):
    /// σ_v = c D₀ Ė with `coefficient` c (s), a damping ratio ζ = c ω / 2
    /// at angular frequency ω. Of the beam named `beam` ("wire" or a
    /// member's name) alone, in place of any other; without `beam`, of
    /// every beam that has none of its own.
    #[pyo3(signature = (coefficient, beam = None))]
    fn kelvin_voigt(&self, coefficient: f64, beam: Option<&str>) -> PyResult<Wire> {
        positive("coefficient", coefficient)?;
        self.damped(Damping::KelvinVoigt { coefficient }, beam)
    }

    /// Rayleigh damping (a scene's `[damping] kind = "rayleigh"`):
    /// Q_d = (mass · M + stiffness · K₀) v, `mass` in 1/s, `stiffness` in s,
    /// K₀ the reference stiffness — for small motions about the reference.
    /// Of the beam named `beam` alone, or of every beam that has none of
    /// its own (as [`Wire::kelvin_voigt`]).
    #[pyo3(signature = (mass = 0.0, stiffness = 0.0, beam = None))]
    fn rayleigh(&self, mass: f64, stiffness: f64, beam: Option<&str>) -> PyResult<Wire> {
        let damping = Damping::Rayleigh { mass, stiffness };
        damping
            .check()
            .map_err(|e| value_error(&e.field, &e.message))?;
        self.damped(damping, beam)
    }

    /// Gravity acceleration, m/s².
    fn gravity(&self, acceleration: Vec<f64>) -> PyResult<Wire> {
        Ok(Wire {
            builder: self
                .builder
                .clone()
                .gravity(vec3("acceleration", acceleration)?),
        })
    }

    /// A constant force (N) at a node (of the member named `beam`; default: the wire).
    #[pyo3(signature = (node, force, beam = None))]
    fn load(&self, node: Whole, force: Vec<f64>, beam: Option<&str>) -> PyResult<Wire> {
        let node = node.0;
        let load = ancf_core::model::PointLoad {
            node,
            force: vec3("force", force)?,
            ..Default::default()
        };
        let builder = self.builder.clone();
        Ok(Wire {
            builder: match beam {
                Some(beam) => builder.load_on(beam, load),
                None => builder.load_with(load),
            },
        })
    }

    /// A rigid rod under the line law: a point on its axis, its direction,
    /// radius (m), stiffness ε_L (N/m²), Coulomb μ, length (m, None:
    /// infinite), and contact damping by a coefficient of restitution
    /// (None: elastic) with its model ("exact", "flores",
    /// "lankarani-nikravesh").
    #[allow(clippy::too_many_arguments)]
    #[pyo3(signature = (center, axis, radius, stiffness, friction=None, length=None, restitution=None, restitution_model=None))]
    fn rod(
        &self,
        center: Vec<f64>,
        axis: Vec<f64>,
        radius: f64,
        stiffness: f64,
        friction: Option<f64>,
        length: Option<f64>,
        restitution: Option<f64>,
        restitution_model: Option<&str>,
    ) -> PyResult<Wire> {
        use ancf_core::model::contact::ContactDamping;
        let damping = ContactDamping::from_keys(restitution, restitution_model)
            .map_err(|e| value_error(&e.field, &e.message))?;
        // Rod::line's own defaults: infinite, frictionless, elastic.
        let mut rod = ancf_core::model::contact::Rod::line(
            vec3("center", center)?,
            vec3("axis", axis)?,
            radius,
            stiffness,
        );
        if let Some(mu) = friction {
            rod = rod.with_friction(mu);
        }
        if let Some(l) = length {
            rod = rod.with_length(l);
        }
        rod.damping = damping;
        rod.check()
            .map_err(|e| value_error(rod_argument(&e.field), &e.message))?;
        Ok(Wire {
            builder: self.builder.clone().rod(rod),
        })
    }

    /// The ground: a plane through `point` (m) with `normal` (towards the
    /// wire's side) under the line law of stiffness ε_L (N/m²), with
    /// Coulomb μ and contact damping by a coefficient of restitution (None:
    /// elastic) with its model, as for rods. The wire touches it, and the
    /// frame members named in `beams` too (the scene file's list, which
    /// names the wire as well; the names are checked when the wire is
    /// built).
    #[pyo3(signature = (point, normal, stiffness, friction=None, restitution=None, restitution_model=None, beams=None))]
    #[allow(clippy::too_many_arguments)]
    fn ground(
        &self,
        point: Vec<f64>,
        normal: Vec<f64>,
        stiffness: f64,
        friction: Option<f64>,
        restitution: Option<f64>,
        restitution_model: Option<&str>,
        beams: Option<Vec<String>>,
    ) -> PyResult<Wire> {
        use ancf_core::model::contact::{ContactDamping, Rod};
        let damping = ContactDamping::from_keys(restitution, restitution_model)
            .map_err(|e| value_error(&e.field, &e.message))?;
        let mut ground = Rod::plane(vec3("point", point)?, vec3("normal", normal)?, stiffness);
        if let Some(mu) = friction {
            ground = ground.with_friction(mu);
        }
        ground.damping = damping;
        ground
            .check()
            .map_err(|e| value_error(rod_argument(&e.field), &e.message))?;
        if let Some(b) = &beams {
            ancf_core::model::contact::check_ground_beams(b)
                .map_err(|e| value_error(&e.field, &e.message))?;
        }
        let builder = self.builder.clone();
        let builder = match &beams {
            Some(b) => {
                builder.ground_touching(ground, &b.iter().map(String::as_str).collect::<Vec<_>>())
            }
            None => builder.ground(ground),
        };
        Ok(Wire { builder })
    }
}

/// A dynamic simulation of a scene. Units: SI (m, s, N, J).
///
/// It computes what `ancf run` computes, bit for bit (checkpoints do not
/// change a run's results).
impl Wire {
    /// This wire with `damping` (checked by the caller) on the beam named
    /// `beam`, or on every beam without its own; a beam must exist when its
    /// damping is given.
    fn damped(&self, damping: Damping, beam: Option<&str>) -> PyResult<Wire> {
        let builder = self.builder.clone();
        Ok(Wire {
            builder: match beam {
                None => builder.damping(damping),
                Some(name) if name == ancf_core::model::WIRE || builder.has_member(name) => {
                    builder.damping_on(name, damping)
                }
                Some(name) => {
                    return Err(value_error(
                        "beam",
                        &format!("no beam is named \"{name}\" (\"wire\" or a member added before)"),
                    ));
                }
            },
        })
    }
}

#[pyclass(module = "ancf")]
pub struct Simulation {
    scene: CoreScene,
    sim: CoreSimulation,
    /// The clearance zones' and the frame members' records, as the
    /// program's run keeps them.
    observed: Observations,
    /// Wall time spent stepping, s (summary's `wall_time_s`), and what the
    /// steps cost (summary's `performance`).
    wall: f64,
    cost: ancf_output::run::Cost,
    /// Total energy at the start (J) and the largest |total + dissipated −
    /// that| at the steps a run writes (summary's `energy.max_drift`).
    drift: (f64, f64),
    /// Whether the run's end was warned of (once).
    end_warned: bool,
}

/// Track the energy drift as the program's run does: at every
/// `output.every`-th step and the last.
fn track_drift(sim: &CoreSimulation, every: usize, drift: &mut (f64, f64)) {
    let (k, n) = sim.steps();
    if k % every.max(1) == 0 || k == n {
        let e = sim.energies();
        drift.1 = drift
            .1
            .max((e.total() + e.dissipated + e.plastic - drift.0).abs());
    }
}

/// A core error as `SimulationError`, with the core's likely cause.
fn simulation_error(e: &CoreSimError) -> PyErr {
    SimulationError::new_err(format!("{e}. Likely cause: {}", e.likely_cause()))
}

impl Simulation {
    /// A simulation of `scene` at its initial state, its clearance zones
    /// observed there.
    fn started(scene: CoreScene, sim: CoreSimulation) -> Self {
        let mut s = Simulation {
            observed: Observations::new(&scene),
            scene,
            wall: 0.0,
            cost: Default::default(),
            drift: (sim.energies().total(), 0.0),
            end_warned: false,
            sim,
        };
        s.observe_state(&[]);
        s
    }

    /// Observe the clearance zones and the frame members at the current
    /// state, the wire's contact force on each member being `member_forces`.
    fn observe_state(&mut self, member_forces: &[[f64; 3]]) {
        let state = self.sim.state();
        (self.observed).observe(
            &self.scene,
            (&state.q, &state.plastic),
            state.time,
            member_forces,
        );
        (self.observed).observe_plastic(
            &self.scene,
            &state.plastic,
            &state.plastic_work,
            state.time,
        );
    }

    fn positions(&self, v: &[f64]) -> Vec<[f64; 3]> {
        let m = self.sim.model();
        m.wire()
            .nodes
            .clone()
            .map(|n| m.node_position(v, n))
            .collect()
    }

    /// The supports' summary so far, as summary.json's `supports`.
    fn support_summaries(&self) -> Vec<ancf_output::output::SupportSummary> {
        let cfc = self.scene.output.cfc;
        let loads = self.sim.support_loads();
        let filtered: Vec<_> = loads.iter().map(|h| h.filtered(cfc)).collect();
        let mut supports = ancf_output::run::supports::dynamic_supports(
            &self.scene.model,
            self.sim.initial_support_forces(),
            self.scene.starts_from_equilibrium(),
            loads,
            &filtered,
            (
                &self.scene.output.response_frequencies,
                self.scene.output.response_damping,
            ),
        );
        ancf_output::run::supports::add_peak_moments(
            &self.scene.model,
            &mut supports,
            self.sim.support_moments(),
        );
        supports
    }

    /// One step; the error names the step and the time.
    /// What the run did that its numbers cannot show (strains past a law's
    /// range, stresses past yield), as summary.json's warnings say it.
    fn run_warnings(&self) -> Vec<String> {
        let mut warnings = self.observed.strain_warnings(&self.scene);
        warnings.extend(self.observed.yield_warnings(&self.scene));
        warnings
    }

    /// At the end time, the run's warnings as Python warnings, once.
    fn warn_at_end(&mut self, py: Python<'_>) -> PyResult<()> {
        if !self.sim.is_finished() || self.end_warned {
            return Ok(());
        }
        self.end_warned = true;
        warn_all(py, &self.run_warnings())
    }

    fn advance(&mut self) -> Result<(), PyErr> {
        let started = std::time::Instant::now();
        let step = self.sim.step();
        let took = started.elapsed().as_secs_f64();
        self.wall += took;
        self.cost.stepping += took;
        let info = step.map_err(|e| simulation_error(&e))?;
        self.cost.add(&info);
        track_drift(&self.sim, self.scene.output.every, &mut self.drift);
        self.observe_state(&info.member_forces);
        Ok(())
    }
}

/// A rod's load into `d` with summary.json's keys.
fn set_load(d: &Bound<'_, PyDict>, load: &ancf_core::loads::rod_load::RodLoad) -> PyResult<()> {
    for (k, v) in [
        ("peak_force", load.peak_force),
        ("peak_time", load.peak_time),
        ("filtered_peak_force", load.filtered_peak_force),
        ("filtered_peak_time", load.filtered_peak_time),
        ("impulse", load.impulse),
        ("contact_duration", load.contact_duration),
        ("cfc", load.cfc),
        (
            "first_impact_filtered_peak",
            load.first_impact_filtered_peak,
        ),
        ("first_impact_impulse", load.first_impact_impulse),
    ] {
        d.set_item(k, v)?;
    }
    d.set_item("first_contact_time", load.first_contact_time)?;
    Ok(())
}

/// A support's entry as summary.json has it (absent values left out): the
/// same serialization, so the two cannot drift.
fn support_dict<'py>(
    py: Python<'py>,
    s: &ancf_output::output::SupportSummary,
) -> PyResult<Bound<'py, PyDict>> {
    let json = serde_json::to_string(s).expect("a support's summary serializes");
    let loads = PyModule::import(py, "json")?.getattr("loads")?;
    Ok(loads.call1((json,))?.cast_into::<PyDict>()?)
}

fn matrix<'py>(py: Python<'py>, rows: &[[f64; 3]]) -> Bound<'py, PyArray2<f64>> {
    let flat: Vec<f64> = rows.iter().flatten().copied().collect();
    PyArray1::from_vec(py, flat)
        .reshape([rows.len(), 3])
        .expect("n × 3 reshape of 3n values")
}

#[pymethods]
impl Simulation {
    /// Starts `scene` (a dynamic scene) at its initial state: the static
    /// equilibrium when the scene says `initial = "static"`, else at rest.
    #[new]
    fn new(py: Python<'_>, scene: &Scene) -> PyResult<Simulation> {
        let Analysis::Dynamic {
            settings,
            initial_static,
            load_steps,
        } = &scene.inner.analysis
        else {
            let err = SceneError::new_err(
                "analysis.kind: Simulation runs dynamic scenes; run a static scene with ancf.run",
            );
            let _ = err.value(py).setattr("field", "analysis.kind");
            return Err(err);
        };
        let initial = if *initial_static {
            Initial::Static {
                load_steps: *load_steps,
            }
        } else {
            Initial::Reference
        };
        let model = scene.inner.model.clone();
        let settings = settings.clone();
        let sim = py
            .detach(move || CoreSimulation::new(&model, settings, initial))
            .map_err(|e| simulation_error(&e))?;
        Ok(Simulation::started(scene.inner.clone(), sim))
    }

    /// Starts a wire built in code at rest, stepping `time_step` (s) up to
    /// `end_time` (s) with generalized-α of spectral radius ρ∞.
    /// `time_step="auto"` chooses each step from the local error estimate
    /// instead, to `error_tolerance` (m of position error per step,
    /// required then) with steps of at most `max_time_step` (s; default
    /// end_time / 100), as `analysis.time_step = "auto"` in a scene file.
    #[staticmethod]
    #[pyo3(signature = (wire, time_step, end_time, spectral_radius=None, error_tolerance=None, max_time_step=None))]
    fn from_wire(
        py: Python<'_>,
        wire: &Wire,
        time_step: &Bound<'_, PyAny>,
        end_time: f64,
        spectral_radius: Option<f64>,
        error_tolerance: Option<f64>,
        max_time_step: Option<f64>,
    ) -> PyResult<Simulation> {
        let (time_step, step_control) =
            stepping(time_step, end_time, error_tolerance, max_time_step)?;
        let settings = ancf_core::solve::dynamics::DynamicSettings {
            time_step,
            step_control,
            end_time,
            spectral_radius: spectral_radius
                .unwrap_or(ancf_core::solve::dynamics::DEFAULT_SPECTRAL_RADIUS),
            ..Default::default()
        };
        settings
            .check()
            .map_err(|e| value_error(&e.field, &e.message))?;
        let model = wire.builder.clone().build().map_err(|e| {
            let err = SceneError::new_err(e.to_string());
            let _ = err.value(py).setattr("field", builder_field(&e));
            err
        })?;
        let implausible = ancf_core::plausibility::model_warnings(&model);
        let scene = CoreScene {
            source: String::new(),
            model,
            analysis: Analysis::Dynamic {
                settings: settings.clone(),
                initial_static: false,
                load_steps: 1,
            },
            output: ancf_core::scene::OutputSettings {
                every: 1,
                checkpoint_every: 0,
                vtk: false,
                vtk_every: None,
                plots: false,
                ..Default::default()
            },
            clearance: Vec::new(),
            implausible,
        };
        warn_all(py, &scene.warnings())?;
        let model = scene.model.clone();
        let sim = py
            .detach(move || CoreSimulation::new(&model, settings, Initial::Reference))
            .map_err(|e| simulation_error(&e))?;
        Ok(Simulation::started(scene, sim))
    }

    /// Advances one time step (the last one ends at the end time).
    fn step(&mut self, py: Python<'_>) -> PyResult<()> {
        if self.sim.is_finished() {
            return Err(SimulationError::new_err(
                "the simulation has reached its end time",
            ));
        }
        self.advance()?;
        self.warn_at_end(py)
    }

    /// Steps until time `until` (s; default: the scene's end time), recording
    /// every `every`-th step and the last; `callback(sim)` is called at each
    /// record. Returns a `RunResult` of NumPy arrays. The steps run without
    /// the GIL; Ctrl-C raises KeyboardInterrupt and leaves the simulation at
    /// its last completed step.
    #[pyo3(signature = (until=None, every=Whole(1), callback=None))]
    fn run(
        slf: &Bound<'_, Self>,
        until: Option<f64>,
        every: Whole,
        callback: Option<Py<PyAny>>,
    ) -> PyResult<RunResult> {
        let every = every.0;
        let py = slf.py();
        if every == 0 {
            return Err(PyValueError::new_err("every: must be at least 1"));
        }
        if until.is_some_and(|t| !t.is_finite()) {
            return Err(PyValueError::new_err("until: must be a finite time in s"));
        }
        let rods = slf
            .borrow()
            .scene
            .model
            .contact()
            .map_or(0, |c| c.rods.len());
        let until = until.unwrap_or(f64::INFINITY);
        let done = move |s: &CoreSimulation| s.has_reached(until);
        let mut result = RunResult::default();
        loop {
            {
                let mut this = slf.borrow_mut();
                if done(&this.sim) {
                    break;
                }
                // Up to `every` steps without the GIL, then a record.
                let this = &mut *this;
                let (sim, scene, observed) = (&mut this.sim, &this.scene, &mut this.observed);
                let drift = &mut this.drift;
                let cost = &mut this.cost;
                let started = std::time::Instant::now();
                let outcome = py.detach(|| {
                    for _ in 0..every {
                        if done(sim) {
                            break;
                        }
                        let begun = std::time::Instant::now();
                        let info = sim.step()?;
                        cost.stepping += begun.elapsed().as_secs_f64();
                        cost.add(&info);
                        let state = sim.state();
                        observed.observe(
                            scene,
                            (&state.q, &state.plastic),
                            state.time,
                            &info.member_forces,
                        );
                        observed.observe_plastic(
                            scene,
                            &state.plastic,
                            &state.plastic_work,
                            state.time,
                        );
                        track_drift(sim, scene.output.every, drift);
                    }
                    Ok(())
                });
                this.wall += started.elapsed().as_secs_f64();
                if let Err(e) = outcome {
                    return Err(simulation_error(&e));
                }
                result.record(this, rods);
            }
            if let Some(cb) = &callback {
                cb.call1(py, (slf.clone(),))?;
            }
            py.check_signals()?;
        }
        slf.borrow_mut().warn_at_end(py)?;
        Ok(result)
    }

    /// Time, s.
    #[getter]
    fn time(&self) -> f64 {
        self.sim.state().time
    }

    /// Steps completed and steps in all.
    #[getter]
    fn steps(&self) -> (usize, usize) {
        self.sim.steps()
    }

    /// The wire's node positions, (n + 1) × 3, m.
    #[getter]
    fn nodes<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.positions(&self.sim.state().q))
    }

    /// The wire's node gradients, (n + 1) × 9: r_x, r_y, r_z one after
    /// the other (final_nodes.csv's rx_x … rz_z): each section's
    /// orientation, twist and stretch.
    #[getter]
    fn gradients<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        let m = self.sim.model();
        let q = &self.sim.state().q;
        let rows: Vec<[f64; 9]> = (m.wire().nodes.clone())
            .map(|n| m.node_gradients(q, n))
            .collect();
        let flat: Vec<f64> = rows.iter().flatten().copied().collect();
        PyArray1::from_vec(py, flat)
            .reshape([rows.len(), 9])
            .expect("n × 9 reshape of 9n values")
    }

    /// Node velocities, (n + 1) × 3, m/s.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.positions(&self.sim.state().v))
    }

    /// Position of the last node, m.
    #[getter]
    fn tip<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let m = self.sim.model();
        PyArray1::from_vec(
            py,
            m.node_position(&self.sim.state().q, m.wire().last_node())
                .to_vec(),
        )
    }

    /// Energies of the current state, J: kinetic, strain, gravity, loads,
    /// contact, total (their sum), dissipated (friction, damping, contact
    /// damping) and, where a layer yields, plastic (its plastic work).
    #[getter]
    fn energies<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let e = self.sim.energies();
        let d = PyDict::new(py);
        for (k, v) in [
            ("kinetic", e.kinetic),
            ("strain", e.strain),
            ("gravity", e.gravity),
            ("loads", e.loads),
            ("contact", e.contact),
            ("total", e.total()),
            ("dissipated", e.dissipated),
        ] {
            d.set_item(k, v)?;
        }
        // As summary.json: only where a layer yields.
        if e.plastic != 0.0 {
            d.set_item("plastic", e.plastic)?;
        }
        Ok(d)
    }

    /// Per rod: the force on it at the last step (N, vector and magnitude)
    /// and its load so far (peaks raw and CFC-filtered, impulse, duration).
    #[getter]
    fn contact<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        let cfc = self.scene.output.cfc;
        for h in self.sim.rod_loads() {
            let d = PyDict::new(py);
            let f = h.force.last().copied().unwrap_or([0.0; 3]);
            d.set_item("force", PyArray1::from_vec(py, f.to_vec()))?;
            d.set_item("force_magnitude", ancf_core::math::vec3::norm(f))?;
            set_load(&d, &h.summary(&h.filtered(cfc)))?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// Per support, in the scene's order: summary.json's `supports[i]`
    /// (beam, node, static_force, peak_force, peak_time,
    /// filtered_peak_force, ratio_to_static, filtered_ratio_to_static, and
    /// with the scene's `output.response_frequencies` its `response`, so
    /// far) and its history: `time` (k, s; t = 0 first) and `force` (k × 3,
    /// N), the force it exerts on the wire.
    #[getter]
    fn supports<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyList>> {
        let list = PyList::empty(py);
        let initial = self.sim.initial_support_forces();
        for (i, (s, h)) in self
            .support_summaries()
            .iter()
            .zip(self.sim.support_loads())
            .enumerate()
        {
            let d = support_dict(py, s)?;
            let mut time = vec![0.0];
            time.extend(&h.time);
            let mut force = vec![initial.get(i).copied().unwrap_or([0.0; 3])];
            force.extend(&h.force);
            d.set_item("time", PyArray1::from_vec(py, time))?;
            d.set_item("force", matrix(py, &force))?;
            list.append(d)?;
        }
        Ok(list)
    }

    /// The run so far with summary.json's keys, as far as a simulation in
    /// progress knows them: status ("running" or "completed"), analysis,
    /// elements, unknowns, time, steps, newton_iterations, factorizations,
    /// step_cuts, kernel, simd (the instruction-set path), tip {position,
    /// displacement}, energy {…, total, dissipated}
    /// and, with rods, contact {first_time, max_normal_force,
    /// max_penetration, rods: [law, contact_stiffness,
    /// stiffness_unit, peak_force, peak_time, filtered_peak_force,
    /// filtered_peak_time, impulse, contact_duration, cfc,
    /// first_contact_time, first_impact_filtered_peak, first_impact_impulse]};
    /// with supports, supports [beam, node, static_force, peak_force,
    /// peak_time, filtered_peak_force, ratio_to_static,
    /// filtered_ratio_to_static]; with clearance zones, clearance [kind,
    /// min_distance, time, position, entered].
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let p = self.sim.progress();
        let model = &self.scene.model;
        let d = PyDict::new(py);
        d.set_item(
            "status",
            if self.sim.is_finished() {
                ancf_output::output::RunStatus::Completed.as_str()
            } else {
                ancf_output::output::RunStatus::Running.as_str()
            },
        )?;
        let (steps, n_steps) = self.sim.steps();
        let message = if self.sim.is_finished() {
            match &self.scene.analysis {
                Analysis::Dynamic { settings, .. } => ancf_output::run::stepping(settings, n_steps),
                Analysis::Static { .. } => format!("{n_steps} steps"),
            }
        } else {
            format!("step {steps} of {n_steps}")
        };
        d.set_item("message", message)?;
        d.set_item("analysis", "dynamic")?;
        d.set_item("elements", model.element_count())?;
        d.set_item("unknowns", model.n_unknowns)?;
        d.set_item("time", p.state.time)?;
        d.set_item("steps", p.step)?;
        d.set_item("newton_iterations", p.newton_iterations)?;
        d.set_item("factorizations", p.factorizations)?;
        d.set_item("step_cuts", p.step_cuts)?;
        d.set_item("kernel", model.element(0).kernel_path().to_string())?;
        d.set_item("simd", ancf_core::math::simd::path().name())?;
        d.set_item("wall_time_s", self.wall)?;
        let loads = PyModule::import(py, "json")?.getattr("loads")?;
        if let Some(t) = ancf_output::output::TimeStepSummary::of(p) {
            let json = serde_json::to_string(&t).expect("time steps serialize");
            d.set_item("time_steps", loads.call1((json,))?)?;
        }
        if let Some(p) = self.cost.summary() {
            let json = serde_json::to_string(&p).expect("performance serializes");
            d.set_item("performance", loads.call1((json,))?)?;
        }
        d.set_item("effects", ancf_output::run::effect_names(model))?;
        let tip = PyDict::new(py);
        let tip_node = model.wire().last_node();
        let position = model.node_position(&p.state.q, tip_node);
        let start = model.node_position(&model.reference, tip_node);
        tip.set_item("position", position.to_vec())?;
        tip.set_item(
            "displacement",
            (0..3).map(|c| position[c] - start[c]).collect::<Vec<f64>>(),
        )?;
        d.set_item("tip", tip)?;
        let energy = self.energies(py)?;
        energy.set_item("max_drift", self.drift.1)?;
        d.set_item("energy", energy)?;
        if let Some(c) = model.contact() {
            // summary.json's own `contact`: the rods, the grounds and their depths.
            let cfc = self.scene.output.cfc;
            let loads = (self.sim.rod_loads().iter())
                .map(|h| h.summary(&h.filtered(cfc)))
                .collect();
            let record = self.sim.contact().copied().unwrap_or_default();
            let contact = ancf_output::run::contact_summary(
                c,
                record.first_time,
                record.max_normal_force,
                record.max_penetration,
                loads,
                &self.observed,
            );
            let contact = serde_json::to_string(&contact).expect("contact serializes");
            let json = PyModule::import(py, "json")?;
            d.set_item("contact", json.call_method1("loads", (contact,))?)?;
        }
        if !model.supports.is_empty() {
            let supports = PyList::empty(py);
            for s in self.support_summaries() {
                supports.append(support_dict(py, &s)?)?;
            }
            d.set_item("supports", supports)?;
        }
        let mut ended = ancf_output::output::Summary {
            beams: self.observed.member_summary(&self.scene),
            ..Default::default()
        };
        let state = self.sim.state();
        let holding = self.scene.model.holding_at(state.time);
        let end = (&state.q[..], Some(&state.v[..]), &state.plastic[..]);
        Observations::fill_permanent_set(&holding, end, &mut ended);
        let members = ended.beams;
        if !members.is_empty() {
            let beams = PyList::empty(py);
            let cfc = self.scene.output.cfc;
            let loads = self.sim.member_loads();
            for (i, m) in members.iter().enumerate() {
                let (b, r) = (PyDict::new(py), &m.record);
                b.set_item("name", &m.name)?;
                if let Some(h) = loads.get(i) {
                    set_load(&b, &h.summary(&h.filtered(cfc)))?;
                }
                for (k, v) in [
                    ("max_bending_moment", r.max_bending_moment),
                    ("max_bending_moment_time", r.max_bending_moment_time),
                    ("max_bending_moment_at", r.max_bending_moment_at),
                    ("max_von_mises", r.max_von_mises),
                    ("max_von_mises_time", r.max_von_mises_time),
                    ("max_von_mises_at", r.max_von_mises_at),
                    (
                        "first_impact_max_bending_moment",
                        r.first_impact_max_bending_moment,
                    ),
                    ("first_impact_max_von_mises", r.first_impact_max_von_mises),
                ] {
                    b.set_item(k, v)?;
                }
                for (k, v) in [
                    ("permanent_set", m.permanent_set),
                    ("permanent_set_at", m.permanent_set_at),
                    ("end_displacement", m.end_displacement),
                    ("end_speed", m.end_speed),
                ] {
                    if let Some(v) = v {
                        b.set_item(k, v)?;
                    }
                }
                beams.append(b)?;
            }
            d.set_item("beams", beams)?;
        }
        let clearance = self.observed.clearance_summary(&self.scene);
        if !clearance.is_empty() {
            let zones = PyList::empty(py);
            for c in &clearance {
                let (z, r) = (PyDict::new(py), &c.record);
                z.set_item("kind", &c.kind)?;
                z.set_item("min_distance", r.min_distance)?;
                z.set_item("time", r.time)?;
                z.set_item("position", r.position.to_vec())?;
                z.set_item("entered", r.entered)?;
                zones.append(z)?;
            }
            d.set_item("clearance", zones)?;
        }
        let strains = serde_json::to_string(&self.observed.strain_summary(&self.scene))
            .expect("strains serialize");
        let json = PyModule::import(py, "json")?;
        d.set_item("strains", json.call_method1("loads", (strains,))?)?;
        // As summary.json: present only when there is something to say.
        let mut warnings = self.scene.warnings();
        warnings.extend(self.run_warnings());
        warnings.extend(ended.warnings);
        if !warnings.is_empty() {
            d.set_item("warnings", warnings)?;
        }
        let b = ancf_output::build_info::BuildInfo::current();
        let build = PyDict::new(py);
        build.set_item("version", b.version)?;
        build.set_item("commit", b.commit)?;
        build.set_item("dirty", b.dirty)?;
        build.set_item("rustc", b.rustc)?;
        build.set_item("kernel_orders", b.kernel_orders)?;
        d.set_item("build", build)?;
        Ok(d)
    }

    fn __repr__(&self) -> String {
        let (k, n) = self.sim.steps();
        format!(
            "ancf.Simulation(t = {:.6} s, step {k} of {n})",
            self.sim.state().time
        )
    }
}

/// Recorded samples of a run, one row per record; every attribute is a
/// NumPy array (float64): time (k, s), tip (k × 3, m), kinetic, strain,
/// gravity, total, dissipated (k, J), rod_force (k × rods, N).
#[pyclass(module = "ancf", frozen)]
#[derive(Default)]
pub struct RunResult {
    time: Vec<f64>,
    tip: Vec<[f64; 3]>,
    kinetic: Vec<f64>,
    strain: Vec<f64>,
    gravity: Vec<f64>,
    total: Vec<f64>,
    dissipated: Vec<f64>,
    rod_force: Vec<Vec<f64>>,
    rods: usize,
}

impl RunResult {
    fn record(&mut self, s: &Simulation, rods: usize) {
        let m = s.sim.model();
        let state = s.sim.state();
        let e = s.sim.energies();
        self.rods = rods;
        self.time.push(state.time);
        self.tip
            .push(m.node_position(&state.q, m.wire().last_node()));
        self.kinetic.push(e.kinetic);
        self.strain.push(e.strain);
        self.gravity.push(e.gravity);
        self.total.push(e.total());
        self.dissipated.push(e.dissipated);
        self.rod_force.push(
            s.sim
                .rod_loads()
                .iter()
                .map(|h| {
                    h.force
                        .last()
                        .map_or(0.0, |f| ancf_core::math::vec3::norm(*f))
                })
                .collect(),
        );
    }
}

#[pymethods]
impl RunResult {
    /// Record times, s.
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.time)
    }
    /// Last node's position at each record, k × 3, m.
    #[getter]
    fn tip<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.tip)
    }
    /// Kinetic energy, J.
    #[getter]
    fn kinetic<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.kinetic)
    }
    /// Strain energy, J.
    #[getter]
    fn strain<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.strain)
    }
    /// Gravity potential, J.
    #[getter]
    fn gravity<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.gravity)
    }
    /// Total mechanical energy, J.
    #[getter]
    fn total<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.total)
    }
    /// Energy dissipated by friction and damping since t = 0, J.
    #[getter]
    fn dissipated<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.dissipated)
    }
    /// |force| on each rod at each record, k × rods, N.
    #[getter]
    fn rod_force<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let flat: Vec<f64> = self.rod_force.iter().flatten().copied().collect();
        PyArray1::from_vec(py, flat).reshape([self.rod_force.len(), self.rods])
    }
    fn __len__(&self) -> usize {
        self.time.len()
    }
    fn __repr__(&self) -> String {
        format!("ancf.RunResult({} records)", self.time.len())
    }
}

/// Runs a scene as `ancf run` does, writing its outputs into `out`; returns
/// summary.json's text. The run goes on a worker thread while this one
/// watches for Ctrl-C: then the run stops at its next step as the CLI's does
/// (status "interrupted", outputs kept) and KeyboardInterrupt is raised.
#[pyfunction]
#[pyo3(signature = (scene, out, quiet=true))]
fn _run(py: Python<'_>, scene: &Scene, out: std::path::PathBuf, quiet: bool) -> PyResult<String> {
    // This run's own token: a KeyboardInterrupt here stops this run only.
    let cancel = ancf_core::solve::cancel::CancelToken::new();
    let opts = ancf_output::run::RunOptions {
        out: out.clone(),
        quiet,
        cancel: cancel.clone(),
    };
    let inner = scene.inner.clone();
    let handle = std::thread::spawn(move || ancf_output::run::run_scene(&inner, &opts));
    while !handle.is_finished() {
        py.detach(|| std::thread::sleep(std::time::Duration::from_millis(20)));
        if let Err(interrupt) = py.check_signals() {
            cancel.cancel();
            let _ = py.detach(|| handle.join());
            return Err(interrupt);
        }
    }
    let summary = handle
        .join()
        .map_err(|_| PyRuntimeError::new_err("the run panicked"))?
        .map_err(PyRuntimeError::new_err)?;
    std::fs::read_to_string(out.join("summary.json")).map_err(|e| {
        PyRuntimeError::new_err(format!(
            "{}: {e} (status {})",
            out.display(),
            summary.status
        ))
    })
}

/// The ring/disk quadrature rule over inner ≤ ρ ≤ outer (the paper's disk/ring rule, Lan, Tian & Yu 2020): arrays y, z, weight.
#[pyfunction]
#[allow(clippy::type_complexity)]
fn quadrature<'py>(
    py: Python<'py>,
    inner: f64,
    outer: f64,
    order: Whole,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
)> {
    let order = order.0;
    if !(inner >= 0.0 && outer > inner && outer.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "need 0 ≤ inner < outer (finite), got inner = {inner}, outer = {outer}"
        )));
    }
    if !(1..=16).contains(&order) {
        return Err(PyValueError::new_err(format!(
            "order: must be 1..=16, got {order}"
        )));
    }
    let points = ancf_core::math::quadrature::ring_rule(order, inner, outer);
    let col = |f: fn(&ancf_core::math::quadrature::SectionPoint) -> f64| {
        PyArray1::from_vec(py, points.iter().map(f).collect())
    };
    Ok((col(|p| p.y), col(|p| p.z), col(|p| p.weight)))
}

/// Panics on purpose: the tests check that a Rust panic reaches Python as
/// an exception and leaves the interpreter running.
#[pyfunction]
fn _panic_for_test() {
    panic!("a deliberate panic inside ancf");
}

#[pymodule]
fn _ancf(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Scene>()?;
    m.add_class::<Simulation>()?;
    m.add_class::<RunResult>()?;
    m.add_class::<Material>()?;
    m.add_class::<Wire>()?;
    m.add_function(wrap_pyfunction!(_run, m)?)?;
    m.add_function(wrap_pyfunction!(quadrature, m)?)?;
    m.add_function(wrap_pyfunction!(_panic_for_test, m)?)?;
    m.add("SceneError", m.py().get_type::<SceneError>())?;
    m.add("SimulationError", m.py().get_type::<SimulationError>())?;
    m.add(
        "PlausibilityWarning",
        m.py().get_type::<PlausibilityWarning>(),
    )?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
