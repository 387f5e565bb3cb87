//! Gathering a sweep: `results.csv` with one row per variant (its values,
//! status, wall time and the summary's design numbers) and `report.md` with
//! plots of each design number against each varied parameter. Works on any
//! sweep folder, also while runs are missing (`ancf sweep --collect DIR`).

use super::{Manifest, SweepEnd, run_dir};
use crate::plot::{Panel, Series, panels_plot};
use serde_json::Value;
use std::fmt::Write as _;
use std::path::Path;

/// Design numbers of one rod, in results.csv's column order.
pub const ROD_COLUMNS: [&str; 8] = [
    "peak_force",
    "peak_time",
    "filtered_peak_force",
    "filtered_peak_time",
    "impulse",
    "first_contact_time",
    "first_impact_filtered_peak",
    "first_impact_impulse",
];

/// Design numbers of one frame member besides its contact's
/// [`ROD_COLUMNS`] (summary.json `beams[i]`): N m and Pa.
pub const MEMBER_COLUMNS: [&str; 4] = [
    "max_bending_moment",
    "max_von_mises",
    "first_impact_max_bending_moment",
    "first_impact_max_von_mises",
];

/// A member's design numbers that only some members have (summary.json
/// `beams[i]`): its utilization by EN 1993-1-1 (a section with a yield
/// stress) and its permanent set, m (a yielding material). Each is a
/// column `NAME_key` where any variant reports it.
pub const MEMBER_DESIGN_COLUMNS: [&str; 2] = ["utilization", "permanent_set"];

/// A ground's numbers besides its [`ROD_COLUMNS`] (summary.json
/// `contact.ground[i]`): how deep the wire went into it, m.
pub const GROUND_COLUMNS: [&str; 1] = ["max_depth"];

/// Design numbers of one support (summary.json `supports[i]`): the force
/// it exerts, raw and CFC-filtered (N), the filtered peak over the static
/// force (the wire's supports, when the run starts from its equilibrium)
/// and over the member's N_pl,Rd (a frame member's, when its section has
/// one); with `output.response_frequencies`, one more column per frequency
/// f, `support{k}_response_{f}hz`: its response's magnitude.
pub const SUPPORT_COLUMNS: [&str; 4] = [
    "peak_force",
    "filtered_peak_force",
    "filtered_ratio_to_static",
    "filtered_ratio_to_limit",
];

/// One frame member's numbers in a variant.
#[derive(Clone, Debug)]
pub struct MemberRow {
    pub name: String,
    /// Its contact with the wire: [`ROD_COLUMNS`].
    pub contact: [Option<f64>; ROD_COLUMNS.len()],
    /// Its internal loads: [`MEMBER_COLUMNS`].
    pub loads: [Option<f64>; MEMBER_COLUMNS.len()],
    /// Its design numbers: [`MEMBER_DESIGN_COLUMNS`].
    pub design: [Option<f64>; MEMBER_DESIGN_COLUMNS.len()],
}

/// One support's numbers in a variant.
#[derive(Clone, Debug)]
pub struct SupportRow {
    /// What it holds: `wire node 0`, `tube0 node 16`.
    pub label: String,
    /// [`SUPPORT_COLUMNS`].
    pub loads: [Option<f64>; SUPPORT_COLUMNS.len()],
    /// With `output.response_frequencies`: per frequency (Hz) the peak of
    /// its response's magnitude (N), summary.json
    /// `supports[i].response[j].peak_magnitude`.
    pub response: Vec<(f64, Option<f64>)>,
}

/// One variant as results.csv has it.
#[derive(Clone, Debug)]
pub struct Row {
    pub id: String,
    pub values: Vec<String>,
    /// completed, failed, interrupted, missing, or the Slurm state of a task
    /// that left no summary (`slurm: TIMEOUT`).
    pub status: String,
    pub message: String,
    pub wall_time_s: Option<f64>,
    /// Per rod: [`ROD_COLUMNS`].
    pub rods: Vec<[Option<f64>; ROD_COLUMNS.len()]>,
    /// Per ground: [`ROD_COLUMNS`], then [`GROUND_COLUMNS`] (columns
    /// `ground{k}_…` when a variant has a ground).
    pub grounds: Vec<Vec<Option<f64>>>,
    /// Per frame member, in the scene's order.
    pub members: Vec<MemberRow>,
    /// Per support, in the scene's order.
    pub supports: Vec<SupportRow>,
    /// Tip displacement components and length, m.
    pub tip: Option<[f64; 4]>,
    pub max_drift: Option<f64>,
    /// Step attempts rejected and cut in halves (summary.json `step_cuts`).
    pub step_cuts: Option<u64>,
    /// Steps completed (summary.json `steps`).
    pub steps: Option<u64>,
    /// What the run was warned of, before it started and after it ended
    /// (summary.json `warnings`).
    pub warnings: Vec<String>,
}

fn number(v: &Value) -> Option<f64> {
    v.as_f64()
}

/// `f` of each entry of the JSON array `v` (none when it is not one).
fn each<T>(v: &Value, f: impl Fn(&Value) -> T) -> Vec<T> {
    v.as_array()
        .map(|a| a.iter().map(f).collect())
        .unwrap_or_default()
}

/// The row of variant `id` from its folder.
fn row(out: &Path, id: &str, values: &[String]) -> Row {
    let dir = run_dir(out, id);
    let summary: Option<Value> = std::fs::read_to_string(dir.join("summary.json"))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok());
    let slurm_state = std::fs::read_to_string(dir.join("slurm_state.txt"))
        .ok()
        .map(|s| s.trim().to_string());
    let Some(s) = summary else {
        let (status, message) = match slurm_state {
            Some(state) if state == "UNKNOWN" => (
                "slurm: UNKNOWN".to_string(),
                "Slurm no longer lists the task and it left no summary.json (cancelled before \
                 it started?); rerun the sweep to resubmit it"
                    .to_string(),
            ),
            Some(state) => (
                format!("slurm: {state}"),
                "the task left no summary.json (see logs/slurm_*.out)".to_string(),
            ),
            None if out.join("logs").join(format!("{id}.log")).exists() => (
                "crashed".to_string(),
                format!("no summary.json; see logs/{id}.log"),
            ),
            None => ("missing".to_string(), "not run yet".to_string()),
        };
        return Row {
            id: id.into(),
            values: values.to_vec(),
            status,
            message,
            wall_time_s: None,
            rods: Vec::new(),
            grounds: Vec::new(),
            members: Vec::new(),
            supports: Vec::new(),
            tip: None,
            max_drift: None,
            step_cuts: None,
            steps: None,
            warnings: Vec::new(),
        };
    };
    let mut status = s["status"].as_str().unwrap_or("unknown").to_string();
    if status != "completed"
        && let Some(state) = slurm_state.filter(|st| st != "COMPLETED")
    {
        status = format!("{status} (slurm: {state})");
    }
    let rods = each(&s["contact"]["rods"], |r| {
        ROD_COLUMNS.map(|k| number(&r[k]))
    });
    let grounds = each(&s["contact"]["ground"], |g| {
        (ROD_COLUMNS.iter().chain(&GROUND_COLUMNS))
            .map(|k| number(&g[*k]))
            .collect()
    });
    let members = each(&s["beams"], |b| MemberRow {
        name: b["name"].as_str().unwrap_or("").to_string(),
        contact: ROD_COLUMNS.map(|k| number(&b[k])),
        loads: MEMBER_COLUMNS.map(|k| number(&b[k])),
        design: MEMBER_DESIGN_COLUMNS.map(|k| number(&b[k])),
    });
    let supports = each(&s["supports"], |p| SupportRow {
        label: format!(
            "{} node {}",
            p["beam"].as_str().unwrap_or("wire"),
            p["node"].as_u64().unwrap_or(0)
        ),
        loads: SUPPORT_COLUMNS.map(|k| number(&p[k])),
        response: each(&p["response"], |r| {
            (
                number(&r["frequency"]).unwrap_or(0.0),
                number(&r["peak_magnitude"]),
            )
        }),
    });
    let d = &s["tip"]["displacement"];
    let tip = match (number(&d[0]), number(&d[1]), number(&d[2])) {
        (Some(x), Some(y), Some(z)) => Some([x, y, z, (x * x + y * y + z * z).sqrt()]),
        _ => None,
    };
    Row {
        id: id.into(),
        values: values.to_vec(),
        status,
        message: s["message"].as_str().unwrap_or("").to_string(),
        wall_time_s: number(&s["wall_time_s"]),
        rods,
        grounds,
        members,
        supports,
        tip,
        max_drift: number(&s["energy"]["max_drift"]),
        step_cuts: s["step_cuts"].as_u64(),
        steps: s["steps"].as_u64(),
        warnings: s["warnings"]
            .as_array()
            .map(|w| {
                w.iter()
                    .filter_map(|x| x.as_str().map(String::from))
                    .collect()
            })
            .unwrap_or_default(),
    }
}

/// The first entry of a linked value's text (`[48.0, [48.0, 0.0, 0.0]]` →
/// `48.0`), as the sweep file writes it.
fn first_item(text: &str) -> Option<String> {
    let v: toml::Table = toml::from_str(&format!("v = {text}")).ok()?;
    match v.get("v")? {
        toml::Value::Array(a) => a.first().map(super::file::value_text),
        _ => None,
    }
}

/// A CSV field, quoted when it holds a comma, a quote or a line break.
fn field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |x| format!("{x:.9e}"))
}

/// The members and supports of the variant that has the most of them (a
/// sweep's variants share them; one that failed early has none), for the
/// columns.
fn layout(rows: &[Row]) -> (&[MemberRow], &[SupportRow]) {
    let members = rows.iter().map(|r| &r.members[..]).max_by_key(|m| m.len());
    let supports = rows.iter().map(|r| &r.supports[..]).max_by_key(|s| s.len());
    (members.unwrap_or(&[]), supports.unwrap_or(&[]))
}

/// results.csv's text.
pub fn csv(parameters: &[String], rows: &[Row]) -> String {
    let n_rods = rows.iter().map(|r| r.rods.len()).max().unwrap_or(0);
    let (members, supports) = layout(rows);
    let mut header: Vec<String> = vec!["id".into()];
    header.extend(parameters.iter().cloned());
    header.extend(["status", "message", "wall_time_s"].map(String::from));
    for k in 0..n_rods {
        header.extend(ROD_COLUMNS.iter().map(|c| format!("rod{k}_{c}")));
    }
    let n_grounds = rows.iter().map(|r| r.grounds.len()).max().unwrap_or(0);
    for k in 0..n_grounds {
        let columns = ROD_COLUMNS.iter().chain(&GROUND_COLUMNS);
        header.extend(columns.map(|c| format!("ground{k}_{c}")));
    }
    // A member's design columns only where some variant reports them.
    let designed: Vec<[bool; MEMBER_DESIGN_COLUMNS.len()]> = (0..members.len())
        .map(|k| {
            std::array::from_fn(|j| {
                rows.iter()
                    .any(|r| r.members.get(k).is_some_and(|m| m.design[j].is_some()))
            })
        })
        .collect();
    for (m, shown) in members.iter().zip(&designed) {
        let columns = ROD_COLUMNS.iter().chain(&MEMBER_COLUMNS);
        header.extend(columns.map(|c| format!("{}_{c}", m.name)));
        for (c, &show) in MEMBER_DESIGN_COLUMNS.iter().zip(shown) {
            if show {
                header.push(format!("{}_{c}", m.name));
            }
        }
    }
    for (k, p) in supports.iter().enumerate() {
        header.extend(SUPPORT_COLUMNS.iter().map(|c| format!("support{k}_{c}")));
        header.extend(
            p.response
                .iter()
                .map(|(f, _)| format!("support{k}_response_{f}hz")),
        );
    }
    header.extend(
        [
            "tip_dx",
            "tip_dy",
            "tip_dz",
            "tip_displacement",
            "energy_max_drift",
            "step_cuts",
            "warnings",
        ]
        .map(String::from),
    );
    let mut s = header
        .iter()
        .map(|h| field(h))
        .collect::<Vec<_>>()
        .join(",")
        + "\n";
    for r in rows {
        let mut cells: Vec<String> = vec![field(&r.id)];
        cells.extend(r.values.iter().map(|v| field(v)));
        cells.extend([field(&r.status), field(&r.message), opt(r.wall_time_s)]);
        for k in 0..n_rods {
            match r.rods.get(k) {
                Some(v) => cells.extend(v.iter().map(|x| opt(*x))),
                None => cells.extend(ROD_COLUMNS.iter().map(|_| String::new())),
            }
        }
        for k in 0..n_grounds {
            match r.grounds.get(k) {
                Some(v) => cells.extend(v.iter().map(|x| opt(*x))),
                None => cells
                    .extend((0..ROD_COLUMNS.len() + GROUND_COLUMNS.len()).map(|_| String::new())),
            }
        }
        for (k, shown) in designed.iter().enumerate() {
            match r.members.get(k) {
                Some(m) => cells.extend(m.contact.iter().chain(&m.loads).map(|x| opt(*x))),
                None => cells
                    .extend((0..ROD_COLUMNS.len() + MEMBER_COLUMNS.len()).map(|_| String::new())),
            }
            for (j, &show) in shown.iter().enumerate() {
                if show {
                    cells.push(opt(r.members.get(k).and_then(|m| m.design[j])));
                }
            }
        }
        for (k, layout) in supports.iter().enumerate() {
            let own = r.supports.get(k);
            match own {
                Some(p) => cells.extend(p.loads.iter().map(|x| opt(*x))),
                None => cells.extend(SUPPORT_COLUMNS.iter().map(|_| String::new())),
            }
            let response = |j: usize| own.and_then(|p| p.response.get(j)).and_then(|r| r.1);
            cells.extend((0..layout.response.len()).map(|j| opt(response(j))));
        }
        match r.tip {
            Some(t) => cells.extend(t.iter().map(|x| opt(Some(*x)))),
            None => cells.extend((0..4).map(|_| String::new())),
        }
        cells.push(opt(r.max_drift));
        cells.push(r.step_cuts.map_or(String::new(), |n| n.to_string()));
        cells.push(field(&r.warnings.join("; ")));
        s += &(cells.join(",") + "\n");
    }
    s
}

/// Writes results.csv and report.md for the sweep in `out`.
pub fn collect(out: &Path) -> Result<SweepEnd, String> {
    let m = Manifest::read(out)?;
    let rows: Vec<Row> = m
        .variants
        .iter()
        .map(|(id, values)| row(out, id, values))
        .collect();
    let io = |e: std::io::Error| format!("{}: {e}", out.display());
    // A completed variant has nothing left to resume: its checkpoint (the
    // whole state, 8 MB on the span break) would only fill the disk.
    for r in rows.iter().filter(|r| r.status == "completed") {
        let checkpoint = run_dir(out, &r.id).join("checkpoint.json");
        if checkpoint.exists() {
            std::fs::remove_file(&checkpoint).map_err(io)?;
        }
    }
    std::fs::write(out.join("results.csv"), csv(&m.parameters, &rows)).map_err(io)?;
    report(out, &m, &rows)?;
    let failed = rows
        .iter()
        .filter(|r| r.status != "completed" && r.status != "missing")
        .count();
    let missing = rows.iter().filter(|r| r.status == "missing").count();
    let warned = rows
        .iter()
        .filter(|r| {
            let cuts = r
                .step_cuts
                .zip(r.steps)
                .is_some_and(|(c, n)| ancf_output::run::many_step_cuts(c as usize, n as usize));
            !r.warnings.is_empty() || cuts
        })
        .count();
    Ok(if failed == 0 && missing == 0 {
        SweepEnd::Completed { warned }
    } else {
        SweepEnd::Incomplete { failed, missing }
    })
}

/// A design number of a row, by name (see [`design_numbers`]).
type Pick = Box<dyn Fn(&Row) -> Option<f64>>;

/// A rod's or member's contact numbers ([`ROD_COLUMNS`]) when the wire
/// touched it (it has a first contact time): an untouched one's zeros are
/// no load, and would only pull the statistics down.
fn when_touched(v: &[Option<f64>; ROD_COLUMNS.len()]) -> Option<&[Option<f64>; ROD_COLUMNS.len()]> {
    v[5].is_some().then_some(v)
}

/// Rod `k`'s numbers in `row` when the wire touched it ([`when_touched`]).
fn touched(row: &Row, k: usize) -> Option<&[Option<f64>; ROD_COLUMNS.len()]> {
    row.rods.get(k).and_then(when_touched)
}

/// `v` with four significant figures (scientific beyond 1e-3 … 1e6).
pub fn significant(v: f64) -> String {
    let m = v.abs();
    if v == 0.0 {
        "0".into()
    } else if (1e-3..1e6).contains(&m) {
        let digits = (3 - m.log10().floor() as i32).max(0) as usize;
        format!("{v:.digits$}")
    } else {
        format!("{v:.3e}")
    }
}

/// The design numbers worth a plot: each rod's filtered peak and impulse,
/// over the run and in its first impact; each frame member's filtered
/// peak, its first impact's filtered peak and impulse, its largest bending
/// moment (in the first impact and over the run) and von Mises stress;
/// each support's filtered peak force (the tower's broken-wire load, a
/// post's load on its footing); the tip displacement and the energy drift.
fn design_numbers(
    n_rods: usize,
    members: &[MemberRow],
    supports: &[SupportRow],
) -> Vec<(String, String, Pick)> {
    let mut out: Vec<(String, String, Pick)> = Vec::new();
    for k in 0..n_rods {
        out.push((
            format!("rod {k}: filtered peak force"),
            "N".into(),
            Box::new(move |r: &Row| touched(r, k).and_then(|v| v[2])),
        ));
        out.push((
            format!("rod {k}: impulse"),
            "N s".into(),
            Box::new(move |r: &Row| touched(r, k).and_then(|v| v[4])),
        ));
        out.push((
            format!("rod {k}: first impact, filtered peak"),
            "N".into(),
            Box::new(move |r: &Row| touched(r, k).and_then(|v| v[6])),
        ));
        out.push((
            format!("rod {k}: first impact, impulse"),
            "N s".into(),
            Box::new(move |r: &Row| touched(r, k).and_then(|v| v[7])),
        ));
    }
    /// Where a member's design number is read: its contact's
    /// [`ROD_COLUMNS`] (none when the wire never touched it), its
    /// [`MEMBER_COLUMNS`], or those only when touched (first-impact loads).
    #[derive(Clone, Copy)]
    enum From {
        Contact(usize),
        Loads(usize),
        TouchedLoads(usize),
    }
    for (k, m) in members.iter().enumerate() {
        for (label, unit, from) in [
            ("filtered peak force", "N", From::Contact(2)),
            ("first impact, filtered peak", "N", From::Contact(6)),
            ("first impact, impulse", "N s", From::Contact(7)),
            (
                "first impact, max bending moment",
                "N m",
                From::TouchedLoads(2),
            ),
            ("max bending moment", "N m", From::Loads(0)),
            ("max von Mises stress", "Pa", From::Loads(1)),
        ] {
            let pick = move |r: &Row| {
                let m = r.members.get(k)?;
                match from {
                    From::Contact(c) => when_touched(&m.contact).and_then(|v| v[c]),
                    From::Loads(c) => m.loads[c],
                    From::TouchedLoads(c) => when_touched(&m.contact).and(m.loads[c]),
                }
            };
            out.push((format!("{}: {label}", m.name), unit.into(), Box::new(pick)));
        }
    }
    for (k, p) in supports.iter().enumerate() {
        // A support released at the start holds nothing: no load to design for.
        out.push((
            format!("support {k} ({}): filtered peak force", p.label),
            "N".into(),
            Box::new(move |r: &Row| {
                r.supports
                    .get(k)
                    .and_then(|p| p.loads[1])
                    .filter(|f| *f > 0.0)
            }),
        ));
        for (j, (f, _)) in p.response.iter().enumerate() {
            out.push((
                format!("support {k} ({}): response at {f} Hz", p.label),
                "N".into(),
                Box::new(move |r: &Row| {
                    let p = r.supports.get(k)?;
                    // As above: a support that held nothing is left out.
                    p.loads[1].filter(|f| *f > 0.0)?;
                    p.response.get(j).and_then(|r| r.1)
                }),
            ));
        }
    }
    out.push((
        "tip displacement".into(),
        "m".into(),
        Box::new(|r: &Row| r.tip.map(|t| t[3])),
    ));
    out.push((
        "energy drift".into(),
        "J".into(),
        Box::new(|r: &Row| r.max_drift),
    ));
    out
}

/// The spread of each design number over the completed variants: an
/// ensemble of slightly perturbed scenes (a sag within its tolerance, a
/// frame within its placement) gives the scatter a single run hides, and
/// its largest value is the envelope a design takes.
fn spread_table(numbers: &[(String, String, Pick)], rows: &[Row], ensemble: bool) -> String {
    let done: Vec<&Row> = rows.iter().filter(|r| r.status == "completed").collect();
    let mut md = String::new();
    if done.len() < 2 {
        return md;
    }
    let _ = writeln!(
        md,
        "\nOver the {} completed variants (spread = (max − min) / mean; n: the \
         variants that have the number — a rod the wire never touched has no load; \
         where: the variant of the extreme):\n",
        done.len()
    );
    let _ = writeln!(
        md,
        "| quantity | n | min | mean | max | spread | min at | max at |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|");
    for (name, unit, pick) in numbers {
        let values: Vec<(f64, &str)> = (done.iter())
            .filter_map(|r| pick(r).map(|v| (v, r.id.as_str())))
            .collect();
        if values.is_empty() {
            continue;
        }
        let first = (values[0], values[0]);
        let ((min, min_at), (max, max_at)) = values.iter().fold(first, |(lo, hi), &v| {
            (
                if v.0 < lo.0 { v } else { lo },
                if v.0 > hi.0 { v } else { hi },
            )
        });
        let mean = values.iter().map(|v| v.0).sum::<f64>() / values.len() as f64;
        let spread = if mean != 0.0 {
            format!("{:.1} %", 100.0 * (max - min) / mean.abs())
        } else {
            "–".into()
        };
        let _ = writeln!(
            md,
            "| {name} ({unit}) | {} | {} | {} | {} | {spread} | {min_at} | {max_at} |",
            values.len(),
            significant(min),
            significant(mean),
            significant(max)
        );
    }
    // Quantiles describe a sample; a grid's chosen values are none.
    if ensemble {
        md += &quantile_table(numbers, &done);
    }
    md
}

/// Each design number's median, 90 % and 95 % quantile over the completed
/// variants with their bootstrap intervals ([`super::quantiles`]).
fn quantile_table(numbers: &[(String, String, Pick)], done: &[&Row]) -> String {
    use super::quantiles::{CONFIDENCE, RESAMPLES, with_interval};
    let mut md = String::new();
    let _ = writeln!(
        md,
        "
Quantiles over the variants, each with its {:.0} % confidence interval \
         (percentile bootstrap, {RESAMPLES} resamples, seeded): the value a design takes \
         at the 90 % or 95 % level, and how well this ensemble pins it down. With few \
         variants an upper quantile's interval reaches the largest value; more variants \
         narrow it as 1/√n.\n",
        100.0 * CONFIDENCE
    );
    let _ = writeln!(md, "| quantity | n | median | 90 % | 95 % |");
    let _ = writeln!(md, "|---|---|---|---|---|");
    for (name, unit, pick) in numbers {
        let values: Vec<f64> = done.iter().filter_map(|r| pick(r)).collect();
        if values.is_empty() {
            continue;
        }
        let cell = |p: f64| {
            let (q, lo, hi) = with_interval(&values, p);
            format!(
                "{} [{}, {}]",
                significant(q),
                significant(lo),
                significant(hi)
            )
        };
        let _ = writeln!(
            md,
            "| {name} ({unit}) | {} | {} | {} | {} |",
            values.len(),
            cell(0.5),
            cell(0.9),
            cell(0.95)
        );
    }
    md
}

/// report.md with a plot per varied parameter.
fn report(out: &Path, m: &Manifest, rows: &[Row]) -> Result<(), String> {
    let n_rods = rows.iter().map(|r| r.rods.len()).max().unwrap_or(0);
    let (members, supports) = layout(rows);
    // Only the numbers some variant has (a released support holds none).
    let mut numbers = design_numbers(n_rods, members, supports);
    numbers.retain(|(_, _, pick)| rows.iter().any(|r| pick(r).is_some()));
    let mut md = String::new();
    let _ = writeln!(md, "# Sweep of {}\n", m.scene.display());
    let done = rows.iter().filter(|r| r.status == "completed").count();
    let _ = writeln!(
        md,
        "{} variants ({} mode over {}), {done} completed. Every number comes from the \
         variant's own `runs/<id>/summary.json`; all of them are in `results.csv`.\n",
        rows.len(),
        match m.mode {
            super::file::Mode::Grid => "grid",
            super::file::Mode::Zip => "zip",
        },
        m.parameters.join(", ")
    );
    let mut head = vec!["id".to_string()];
    head.extend(m.parameters.iter().cloned());
    head.push("status".into());
    head.extend(numbers.iter().map(|(n, u, _)| format!("{n} ({u})")));
    let _ = writeln!(md, "| {} |", head.join(" | "));
    let _ = writeln!(md, "|{}", "---|".repeat(head.len()));
    for r in rows {
        let mut cells = vec![r.id.clone()];
        cells.extend(r.values.iter().cloned());
        cells.push(r.status.clone());
        cells.extend(
            numbers
                .iter()
                .map(|(_, _, f)| f(r).map_or("–".into(), significant)),
        );
        let _ = writeln!(md, "| {} |", cells.join(" | "));
    }
    md.push_str(&spread_table(&numbers, rows, m.ensemble));
    let warned: Vec<String> = rows
        .iter()
        .flat_map(|r| r.warnings.iter().map(move |w| format!("* {}: {w}", r.id)))
        .collect();
    if !warned.is_empty() {
        let _ = writeln!(
            md,
            "\nWarned before they ran (their numbers depend on what the warning says):\n\n{}\n",
            warned.join("\n")
        );
    }
    let plots = out.join("plots");
    std::fs::create_dir_all(&plots).map_err(|e| format!("{}: {e}", plots.display()))?;
    for (p, name) in m.parameters.iter().enumerate() {
        // x: the value where all of this parameter's values are numbers,
        // else its position in the list (the legend below says which).
        let distinct: Vec<&String> = {
            let mut d: Vec<&String> = Vec::new();
            for (_, v) in &m.variants {
                if !d.contains(&&v[p]) {
                    d.push(&v[p]);
                }
            }
            d
        };
        if distinct.len() < 2 {
            let _ = writeln!(
                md,
                "\n## Against {name}\n\nOne value ({}) in every variant: nothing to plot.\n",
                distinct.first().map_or("", |v| v.as_str())
            );
            continue;
        }
        // Linked paths (`a & b`) are plotted against the first path's value.
        let linked = name.contains('&');
        let first_path = name.split('&').next().unwrap_or(name).trim().to_string();
        let lead = |v: &str| {
            if linked {
                first_item(v)
            } else {
                Some(v.to_string())
            }
        };
        let xs: Vec<Option<f64>> = distinct
            .iter()
            .map(|v| lead(v).and_then(|t| t.parse::<f64>().ok()))
            .collect();
        let numeric = xs.iter().all(Option::is_some) && {
            let mut sorted: Vec<f64> = xs.iter().flatten().copied().collect();
            sorted.sort_by(f64::total_cmp);
            sorted.windows(2).all(|w| w[0] < w[1])
        };
        let x_of = |v: &String| {
            let i = distinct.iter().position(|d| *d == v).unwrap_or(0);
            if numeric {
                xs[i].unwrap_or(f64::NAN)
            } else {
                i as f64
            }
        };
        // One line per combination of the other parameters' values.
        let mut groups: Vec<(String, Vec<&Row>)> = Vec::new();
        for r in rows {
            let key: Vec<String> = m
                .parameters
                .iter()
                .zip(&r.values)
                .enumerate()
                .filter(|(q, _)| *q != p)
                .map(|(_, (n, v))| {
                    // A linked parameter by its first path only (legends stay short).
                    match n.split_once('&') {
                        Some((first, _)) => {
                            format!(
                                "{} = {}",
                                first.trim(),
                                first_item(v).unwrap_or_else(|| v.clone())
                            )
                        }
                        None => format!("{n} = {v}"),
                    }
                })
                .collect();
            let key = if key.is_empty() {
                name.clone()
            } else {
                key.join(", ")
            };
            match groups.iter_mut().find(|(k, _)| *k == key) {
                Some((_, g)) => g.push(r),
                None => groups.push((key, vec![r])),
            }
        }
        let x_label = if numeric {
            first_path.clone()
        } else {
            format!("{first_path} (position in its list)")
        };
        let titles: Vec<String> = numbers
            .iter()
            .map(|(n, u, _)| format!("{n}, {u}"))
            .collect();
        let panels: Vec<Panel> = numbers
            .iter()
            .zip(&titles)
            .map(|((_, _, f), title)| Panel {
                title,
                x_label: &x_label,
                y_label: "",
                series: groups
                    .iter()
                    .map(|(label, g)| {
                        let mut points: Vec<(f64, f64)> = g
                            .iter()
                            .filter_map(|r| f(r).map(|y| (x_of(&r.values[p]), y)))
                            .collect();
                        points.sort_by(|a, b| a.0.total_cmp(&b.0));
                        Series { label, points }
                    })
                    .collect(),
                marks: Vec::new(),
                markers: true,
            })
            .collect();
        let file = format!(
            "{}.png",
            name.chars()
                .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
                .collect::<String>()
        );
        let cols = 2;
        let rows_n = panels.len().div_ceil(cols);
        panels_plot(&plots.join(&file), rows_n, cols, (560, 360), &panels)?;
        let _ = writeln!(md, "\n## Against {name}\n\n![{name}](plots/{file})\n");
        if !numeric {
            for (i, v) in distinct.iter().enumerate() {
                let _ = writeln!(md, "- position {i}: {name} = {v}");
            }
        }
    }
    let failed: Vec<&Row> = rows.iter().filter(|r| r.status != "completed").collect();
    if !failed.is_empty() {
        let _ = writeln!(md, "\n## Not completed\n");
        for r in failed {
            let _ = writeln!(md, "- {}: {} — {}", r.id, r.status, r.message);
        }
    }
    std::fs::write(out.join("report.md"), md).map_err(|e| format!("{}: {e}", out.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A member's design columns appear where some variant reports them,
    /// each in its own column, blank where a variant has none.
    #[test]
    fn a_members_design_numbers_get_columns_where_any_variant_has_them() {
        let out = std::env::temp_dir().join(format!("ancf-results-{}", std::process::id()));
        let write = |id: &str, tube: &str| {
            let dir = run_dir(&out, id);
            std::fs::create_dir_all(&dir).unwrap();
            let text = format!(
                r#"{{"status": "completed", "beams": [{{"name": "tube", {tube}}}, {{"name": "post"}}]}}"#
            );
            std::fs::write(dir.join("summary.json"), text).unwrap();
        };
        write("a", r#""utilization": 1.1, "permanent_set": 0.002"#);
        write("b", r#""utilization": 0.5"#);
        let rows = [row(&out, "a", &["1".into()]), row(&out, "b", &["2".into()])];
        let text = csv(&["c".into()], &rows);
        std::fs::remove_dir_all(&out).unwrap();
        let lines: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
        let column = |name: &str| lines[0].iter().position(|h| *h == name);
        let (u, set) = (column("tube_utilization"), column("tube_permanent_set"));
        assert!(column("post_utilization").is_none() && column("post_permanent_set").is_none());
        let (u, set) = (u.expect("utilization column"), set.expect("set column"));
        assert_eq!(set, u + 1);
        let value = |l: usize, c: usize| lines[l][c].parse::<f64>().ok();
        assert_eq!((value(1, u), value(1, set)), (Some(1.1), Some(0.002)));
        assert_eq!((value(2, u), lines[2][set]), (Some(0.5), ""));
    }
}
