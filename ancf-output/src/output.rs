//! Output files of a run. Each is written as the run goes (time series
//! rows are flushed as they are produced), so a failed run keeps what it
//! computed.

use ancf_core::solve::dynamics::Energies;
use serde::Serialize;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

/// Energies reported in the summary (J): the last written state's
/// kinetic, strain, gravity, loads, contact and dissipated energies and,
/// with a yielding layer, the plastic work (the keys of [`Energies`]),
/// then `total` and `max_drift`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct EnergySummary {
    #[serde(flatten)]
    pub last: Energies,
    /// Mechanical energy: kinetic + strain + gravity + loads + contact.
    pub total: f64,
    /// Largest |E(t) + dissipated(t) + plastic(t) − E(0)| over the written
    /// steps, J.
    pub max_drift: f64,
}

#[derive(Clone, Debug, Default, Serialize)]
pub struct TipSummary {
    /// Last node's position r, m.
    pub position: [f64; 3],
    /// Last node's displacement from the reference, m.
    pub displacement: [f64; 3],
}

/// Contact statistics of a run with rods.
#[derive(Clone, Debug, Default, Serialize, serde::Deserialize)]
pub struct ContactSummary {
    /// Time of the first contact, s (null: never touched).
    pub first_time: Option<f64>,
    /// Largest total normal force, N.
    pub max_normal_force: f64,
    /// Largest penetration, m.
    pub max_penetration: f64,
    /// Per rod, in the scene's order.
    pub rods: Vec<RodSummary>,
    /// Per ground, in the scene's order (absent without one).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ground: Vec<GroundSummary>,
}

impl ContactSummary {
    /// The rods' and the grounds' entries in the model's partner order
    /// (the rods, then the grounds): one per load history.
    pub fn rigid(&self) -> Vec<&RodSummary> {
        (self.rods.iter())
            .chain(self.ground.iter().map(|g| &g.contact))
            .collect()
    }
}

/// One ground's load, as a rod's, and how deep the wire went into it.
#[derive(Clone, Debug, Default, Serialize, serde::Deserialize)]
pub struct GroundSummary {
    /// Law, stiffness, restitution and the load (peaks raw and CFC
    /// filtered, impulse, duration), with a rod's keys.
    #[serde(flatten)]
    pub contact: RodSummary,
    /// The deepest the wire's surface went below the plane, m (0 when it
    /// never did): centerline points a quarter element apart, at every
    /// written state. Deeper than the wire's radius, its centerline passed
    /// the plane: the contact stiffness or the time step is too coarse.
    pub max_depth: f64,
    /// When, s.
    pub max_depth_time: f64,
    /// Where: the centerline point, m.
    pub max_depth_at: [f64; 3],
}

/// One rod's load: what a frame designer needs.
#[derive(Clone, Debug, Default, Serialize, serde::Deserialize)]
pub struct RodSummary {
    /// Contact law: "line", "hertz" or "surface".
    pub law: String,
    /// Penalty stiffness used (hertz: derived from the materials).
    pub contact_stiffness: f64,
    /// Its unit: "N/m^2" (line, hertz) or "N/m^3" (surface).
    pub stiffness_unit: String,
    /// Coefficient of restitution of the contact damping (absent: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution: Option<f64>,
    /// How the damping follows from it: "exact", "flores" or "lankarani-nikravesh".
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution_model: Option<String>,
    /// Peaks (raw and CFC-filtered), impulse, contact duration; for a
    /// static run the final force is the peak.
    #[serde(flatten)]
    pub load: ancf_core::loads::rod_load::RodLoad,
}

/// One support's load: the force it exerts on the body it holds (N). After
/// a span breaks, the remaining support's peak is the tower's broken-wire
/// load and `ratio_to_static` its dynamic amplification.
#[derive(Clone, Debug, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct SupportSummary {
    /// The body held: "wire" or a member's name.
    pub beam: String,
    /// The node held, counted on that beam.
    pub node: usize,
    /// The force in the static equilibrium (N): a static run's result; in a
    /// dynamic run, the force at t = 0 (the static reaction when the run
    /// starts from a static equilibrium, `analysis.initial_static`).
    pub static_force: [f64; 3],
    /// Dynamic runs: the largest |F| over the steps (N) …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_force: Option<f64>,
    /// … its time (s) …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_time: Option<f64>,
    /// … the largest CFC-filtered |F| (N, `output.cfc`) …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filtered_peak_force: Option<f64>,
    /// … and, for a support of the wire, the peak over the static force's
    /// magnitude, `peak_force / |static_force|` (absent when the static
    /// force is zero, and when the run does not start from a static
    /// equilibrium) …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ratio_to_static: Option<f64>,
    /// … and the same for the filtered peak.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filtered_ratio_to_static: Option<f64>,
    /// A support of a frame member whose section has a design resistance
    /// ([`ancf_core::loads::design_check`]): the member's own limit, its
    /// section's N_pl,Rd = A f_y (N). A post's self-weight reaction says
    /// nothing of how near its limit a blow takes it; this does …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limit_force: Option<f64>,
    /// … the peak |F| over it (a static run: |static_force|) …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ratio_to_limit: Option<f64>,
    /// … the filtered peak over it …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub filtered_ratio_to_limit: Option<f64>,
    /// … its section's bending resistance M_pl,Rd (class 1–2, M_el,Rd
    /// class 3; N m) …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limit_moment: Option<f64>,
    /// … and, where the support has springs that carry a moment,
    /// `peak_moment` over it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub moment_ratio_to_limit: Option<f64>,
    /// Dynamic runs with `output.response_frequencies`: what a structure
    /// with one mode at each frequency feels from the force.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub response: Vec<SupportResponse>,
    /// A support with a rotational or torsional spring: the largest |M|
    /// its springs exert on the body (N m; a static run: at equilibrium),
    /// what sizes a coupler or a post's head …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_moment: Option<f64>,
    /// … and its time (s; dynamic runs).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub peak_moment_time: Option<f64>,
}

/// The largest response of oscillators of one frequency driven by a
/// support's force, one per component ([`ancf_core::loads::response`]):
/// the equivalent static force a structure with that mode carries.
#[derive(Clone, Debug, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct SupportResponse {
    /// The oscillators' frequency (Hz) …
    pub frequency: f64,
    /// … and damping ratio.
    pub damping: f64,
    /// The largest |u| of the x, y and z components' oscillators (N).
    pub peak: [f64; 3],
    /// The largest |u| of the three side by side, a vector (N): the
    /// response's magnitude, which the ratios compare.
    #[serde(default)]
    pub peak_magnitude: f64,
    /// `peak_magnitude` over |static_force| (as `ratio_to_static`) …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ratio_to_static: Option<f64>,
    /// … or over the member's `limit_force` (as `ratio_to_limit`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ratio_to_limit: Option<f64>,
}

/// A frame member's largest internal loads over the run (`[[beam]]`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct BeamSummary {
    /// The member's name.
    pub name: String,
    /// The largest bending moment (N m), its time (s) and place (m from
    /// the member's first node); the largest von Mises stress at the outer
    /// fiber (Pa), its time and place.
    #[serde(flatten)]
    pub record: ancf_core::loads::member_load::MemberRecord,
    /// The wire's contact force on the member as a rod's is reported: first
    /// contact time, raw and CFC-filtered peaks, impulse, first impact (a
    /// static run: the force at equilibrium as both peaks).
    #[serde(flatten)]
    pub contact: ancf_core::loads::rod_load::RodLoad,
    /// A member with an elastic-plastic layer: its permanent set, the
    /// largest distance between its rest shapes after and before the run
    /// (m), each a static equilibrium of the member alone — its supports,
    /// springs and own weight, the wire lifted off — the one after with the
    /// plastic history the run left (see
    /// [`ancf_core::solve::permanent_set`]); `None` where no rest shape was
    /// found (a warning says why) …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub permanent_set: Option<f64>,
    /// … and where (m from its first node).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub permanent_set_at: Option<f64>,
    /// A member with an elastic-plastic layer: the largest displacement of
    /// its nodes from the reference at the run's end (m), vibration, the
    /// wire's weight and the supports' give included …
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end_displacement: Option<f64>,
    /// … and its nodes' largest speed then (m/s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end_speed: Option<f64>,
}

/// What a dynamic run's steps cost against the least a step can cost: one
/// force evaluation and one linear solve of the same model, timed inside
/// the run (so both share the machine's load). The limit ratio is a
/// scene's cost on any CPU: 1 would be one Newton iteration per step with
/// no overhead.
#[derive(Clone, Debug, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct PerformanceSummary {
    /// Wall time per accepted step (µs), the stepping alone (no output).
    pub step_us: f64,
    /// One force evaluation without a Jacobian (µs, the mean in the run).
    pub force_us: f64,
    /// One solve with the factored Newton matrix (µs, the mean).
    pub solve_us: f64,
    /// step_us / (force_us + solve_us).
    pub limit_ratio: f64,
    /// The part of `limit_ratio` the Newton method's own work takes: the
    /// run's force evaluations, solves, Jacobians and factorizations per
    /// step, at their measured times, over force_us + solve_us. What the
    /// ratio would be with every other cost (residual bookkeeping, M a,
    /// the energy guard, the contact search, copies) removed; lowering it
    /// takes fewer iterations or refreshes, not less overhead.
    #[serde(default)]
    pub newton_ratio: f64,
    /// Newton iterations per accepted step (rejected attempts' included).
    pub iterations_per_step: f64,
    /// Force evaluations without a Jacobian per accepted step (a step that
    /// converges with its kept matrix makes one more than its iterations:
    /// the last shows convergence).
    #[serde(default)]
    pub evaluations_per_step: f64,
    /// One force evaluation with the Jacobian (µs, the mean; 0 when the
    /// process formed none, as a run resumed with its kept matrix may).
    #[serde(default)]
    pub jacobian_us: f64,
    /// One factorization of the Newton matrix (µs, the mean; 0 when none).
    #[serde(default)]
    pub factorization_us: f64,
    /// Newton matrix factorizations and rejected step attempts.
    pub factorizations: usize,
    pub rejected: usize,
}

/// A beam's largest strains over the run (the wire first, then each
/// member): the centerline's and each layer's outer fibres' largest
/// |E_xx| with time and place, and the largest stretch of the whole beam.
#[derive(Clone, Debug, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct StrainSummary {
    /// "wire" or the member's name.
    pub beam: String,
    #[serde(flatten)]
    pub record: ancf_core::loads::strain_record::StrainRecord,
    /// What each of `layers` is, from the centre out: `"material"`, the
    /// layer's own fibre strain (ω = 1: the section bends as one solid),
    /// or `"continuum"` (ω < 1: the continuum element's strain at the
    /// layer's outer radius, bending a whole section; a stranded layer's
    /// strands bend about their own axes and strain far less, so read the
    /// centerline's `axial` for what stretches the strands).
    #[serde(default)]
    pub layer_strains: Vec<String>,
}

impl StrainSummary {
    /// The names of `layer_strains` for `section`'s layers.
    pub fn layer_kinds(section: &ancf_core::section::Section) -> Vec<String> {
        use ancf_core::material::MaterialModel;
        (section.layers.iter())
            .map(|l| match l.material.model {
                MaterialModel::StVenantKirchhoff { bending_factor, .. } if bending_factor < 1.0 => {
                    "continuum".to_string()
                }
                _ => "material".to_string(),
            })
            .collect()
    }
}

/// How close the wire came to a clearance zone (`[[clearance]]`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct ClearanceSummary {
    /// "box" or "half-space".
    pub kind: String,
    /// The smallest distance of the wire's surface (m; negative: how deep
    /// it entered), its time (s) and the centerline point (m); whether the
    /// wire entered the zone.
    #[serde(flatten)]
    pub record: ancf_core::loads::clearance_record::ClearanceRecord,
}

/// The steps of a dynamic run (summary.json's `time_steps`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct TimeStepSummary {
    /// Whether the steps were chosen by the error estimate
    /// (`analysis.time_step = "auto"`).
    pub adaptive: bool,
    /// The shortest, the longest and the mean step completed (s).
    pub shortest_s: f64,
    pub longest_s: f64,
    pub mean_s: f64,
    /// Converged attempts the error estimate rejected and tried again
    /// shorter (adaptive runs; their work is in the run's counts).
    pub retried: usize,
}

impl TimeStepSummary {
    /// From a simulation's progress; `None` before its first step.
    pub fn of(progress: &ancf_core::solve::simulation::Snapshot) -> Option<Self> {
        let [shortest_s, longest_s] = progress.step_range?;
        Some(TimeStepSummary {
            adaptive: progress.step_size.is_some(),
            shortest_s,
            longest_s,
            mean_s: progress.state.time / progress.step.max(1) as f64,
            retried: progress.step_retries,
        })
    }
}

/// How a run ended (summary.json's `status`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RunStatus {
    /// Not ended yet.
    #[default]
    Running,
    /// Reached its end time (or static equilibrium).
    Completed,
    /// Stopped by a numerical failure, named in the message.
    Failed,
    /// Stopped by its cancellation token (Ctrl-C, a termination signal, a
    /// Python KeyboardInterrupt); what it wrote is kept.
    Interrupted,
}

impl RunStatus {
    /// The name summary.json and the sweep tables use.
    pub fn as_str(self) -> &'static str {
        match self {
            RunStatus::Running => "running",
            RunStatus::Completed => "completed",
            RunStatus::Failed => "failed",
            RunStatus::Interrupted => "interrupted",
        }
    }
}

impl std::fmt::Display for RunStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.as_str())
    }
}

/// `summary.json`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct Summary {
    /// How the run ended.
    pub status: RunStatus,
    pub message: String,
    /// "static" or "dynamic".
    pub analysis: String,
    pub elements: usize,
    pub unknowns: usize,
    /// Final simulated time, s (static: 0).
    pub time: f64,
    /// Time steps (dynamic) or load steps (static) completed.
    pub steps: usize,
    /// Newton iterations and factorizations, those of rejected attempts
    /// included (the work the run cost).
    pub newton_iterations: usize,
    pub factorizations: usize,
    /// Dynamic: step attempts rejected (Newton failed, the energy guard or
    /// the penetration limit) and cut in halves.
    pub step_cuts: usize,
    pub wall_time_s: f64,
    /// Which element kernel ran.
    pub kernel: String,
    /// The instruction-set path of the hot loops (`baseline`, `avx2`, `avx512`).
    pub simd: String,
    pub tip: TipSummary,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub energy: Option<EnergySummary>,
    /// The model's effects, by name.
    pub effects: Vec<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactSummary>,
    /// Per support, in the scene's order: the force it exerts (absent
    /// without supports).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub supports: Vec<SupportSummary>,
    /// Per frame member, in the scene's order (absent without any).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub beams: Vec<BeamSummary>,
    /// Per clearance zone, in the scene's order (absent without any).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub clearance: Vec<ClearanceSummary>,
    /// Per beam, the wire first: its largest strains over the run.
    pub strains: Vec<StrainSummary>,
    /// Dynamic runs: the steps' sizes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time_steps: Option<TimeStepSummary>,
    /// Dynamic runs: what the steps cost against one force evaluation and
    /// one solve (timings of this process; a resumed run's from its resume).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub performance: Option<PerformanceSummary>,
    /// What the scene will likely do badly, known before the run
    /// ([`ancf_core::scene::Scene::warnings`]), and what the run showed
    /// to be out of range (energy gained, strains beyond a law's range,
    /// [`ancf_core::plausibility`]); absent when there is nothing to say.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// The program that computed it (version, commit, compiler, kernels).
    pub build: crate::build_info::BuildInfo,
}

impl Summary {
    pub fn write(&self, dir: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).expect("summary serializes");
        std::fs::write(dir.join("summary.json"), text + "\n")
    }
}

/// `timeseries.csv`, one row per written step, flushed row by row.
pub struct TimeSeries {
    table: Table,
}

pub const TIMESERIES_HEADER: &str =
    "time,tip_x,tip_y,tip_z,kinetic,strain,gravity,total,loads,newton_iterations";

impl TimeSeries {
    /// With rods, the columns `contact_force,penetration,contact_energy,dissipated` follow;
    /// `time_step` (the size of the step that ended at the row's time, s; 0 at t = 0) ends
    /// every row.
    pub fn create(dir: &Path, contact: bool) -> std::io::Result<Self> {
        let header = if contact {
            format!(
                "{TIMESERIES_HEADER},contact_force,penetration,contact_energy,dissipated,time_step"
            )
        } else {
            format!("{TIMESERIES_HEADER},time_step")
        };
        Ok(TimeSeries {
            table: Table::create(&dir.join("timeseries.csv"), &header)?,
        })
    }

    /// Continue an existing `timeseries.csv` (a resumed run).
    pub fn append(dir: &Path) -> std::io::Result<Self> {
        Ok(TimeSeries {
            table: Table::append(&dir.join("timeseries.csv"))?,
        })
    }

    pub fn row(&mut self, values: &[f64]) -> std::io::Result<()> {
        self.table.row(values)
    }
}

/// A CSV file written row by row (flushed), for extra time series.
pub struct Table {
    file: BufWriter<File>,
}

impl Table {
    pub fn create(path: &Path, header: &str) -> std::io::Result<Self> {
        let mut file = BufWriter::new(File::create(path)?);
        writeln!(file, "{header}")?;
        Ok(Table { file })
    }

    /// Continue an existing table.
    pub fn append(path: &Path) -> std::io::Result<Self> {
        Ok(Table {
            file: BufWriter::new(std::fs::OpenOptions::new().append(true).open(path)?),
        })
    }

    pub fn row(&mut self, values: &[f64]) -> std::io::Result<()> {
        let line: Vec<String> = values.iter().map(|v| format!("{v:.12e}")).collect();
        writeln!(self.file, "{}", line.join(","))?;
        self.file.flush()
    }
}

/// The columns of `final_nodes.csv` after `node`: the position (m) and
/// the gradients r_x, r_y, r_z (dimensionless), a node's twelve
/// coordinates in order.
pub const FINAL_NODE_COLUMNS: [&str; 12] = [
    "x", "y", "z", "rx_x", "rx_y", "rx_z", "ry_x", "ry_y", "ry_z", "rz_x", "rz_y", "rz_z",
];

/// `final_nodes.csv` (or a member's `final_nodes_NAME.csv`) at `path`: a
/// beam's nodes at the end of the run, each its position and gradients
/// ([`FINAL_NODE_COLUMNS`]): where it is, and how its section is turned,
/// twisted and stretched.
pub fn write_final_nodes(path: &Path, nodes: &[[f64; 12]]) -> std::io::Result<()> {
    let mut f = BufWriter::new(File::create(path)?);
    writeln!(f, "node,{}", FINAL_NODE_COLUMNS.join(","))?;
    for (i, node) in nodes.iter().enumerate() {
        let values: Vec<String> = node.iter().map(|v| format!("{v:.12e}")).collect();
        writeln!(f, "{i},{}", values.join(","))?;
    }
    f.flush()
}
