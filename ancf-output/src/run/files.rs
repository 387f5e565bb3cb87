//! The files of a run in its output directory, written as the run goes
//! (so a failed or interrupted run keeps what it computed): timeseries.csv
//! row by row, VTK frames, checkpoints, and at the end rod_forces.csv,
//! supports.csv, contact_point.csv, final_nodes.csv and summary.json.

use super::Progress;
use super::history::History;
use super::plots::PlotJob;
use crate::output::{Summary, TimeSeries, write_final_nodes};
use crate::vtk::VtkWriter;
use ancf_core::forces::contact::ContactSample;
use ancf_core::loads::rod_load::{Filtered, LoadHistory};
use ancf_core::math::vec3::norm;
use ancf_core::model::Model;
use ancf_core::scene::Scene;
use ancf_core::solve::dynamics::{Energies, State};
use std::path::{Path, PathBuf};

/// An I/O error as the message of a failed run, naming the file (or
/// folder) the write was for.
pub fn io_err(path: &Path, e: std::io::Error) -> String {
    format!("cannot write to {}: {e}", path.display())
}

/// The format of `checkpoint.json` this version writes and reads.
pub const CHECKPOINT_VERSION: u32 = 2;

/// `checkpoint.json`: the scene and the progress after a step, with the
/// format's version and a checksum of both (verified before a resume).
#[derive(serde::Serialize, serde::Deserialize)]
pub struct Checkpoint {
    /// [`CHECKPOINT_VERSION`] (absent in files of earlier versions).
    #[serde(default)]
    pub version: u32,
    /// CRC-32 (hex) of the scene's text, a newline and the progress as
    /// serialized here.
    #[serde(default)]
    pub checksum: String,
    /// The scene file's text.
    pub scene: String,
    /// Everything the run had accumulated.
    pub progress: Progress,
}

impl Checkpoint {
    /// The checkpoint of `scene`'s text at `progress`.
    pub fn new(scene: String, progress: Progress) -> Result<Self, String> {
        let checksum = checksum(&scene, &progress)?;
        Ok(Checkpoint {
            version: CHECKPOINT_VERSION,
            checksum,
            scene,
            progress,
        })
    }

    /// Read and verify `path`: its format version and its checksum; what
    /// is wrong is named with the file and the field.
    pub fn read(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path)
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
        let ck: Checkpoint =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", path.display()))?;
        if ck.version != CHECKPOINT_VERSION {
            return Err(format!(
                "{}: version is {}, this ancf reads version {CHECKPOINT_VERSION}; start the run \
                 again (without --resume)",
                path.display(),
                ck.version
            ));
        }
        if checksum(&ck.scene, &ck.progress)? != ck.checksum {
            return Err(format!(
                "{}: checksum does not match the contents (the file was changed or damaged); \
                 start the run again (without --resume)",
                path.display()
            ));
        }
        Ok(ck)
    }
}

/// CRC-32 (hex) of the scene's text, a newline and the serialized progress.
fn checksum(scene: &str, progress: &Progress) -> Result<String, String> {
    let text = serde_json::to_string(progress).map_err(|e| format!("checkpoint: {e}"))?;
    let mut h = crc32fast::Hasher::new();
    h.update(scene.as_bytes());
    h.update(b"\n");
    h.update(text.as_bytes());
    Ok(format!("{:08x}", h.finalize()))
}

/// A dynamic run's open files.
pub struct Files {
    dir: PathBuf,
    series: TimeSeries,
    vtk: Option<VtkWriter>,
}

impl Files {
    /// The files in `dir` (which exists): new ones, or with `resume` the
    /// files of the run checkpointed there, cut back to the checkpoint's
    /// time and continued. VTK frames when the scene asks.
    pub fn open(dir: &Path, scene: &Scene, resume: Option<&Progress>) -> Result<Self, String> {
        let model = &scene.model;
        let vtk_dir = dir.join("vtk");
        let (series, vtk) = match resume {
            None => (
                TimeSeries::create(dir, model.contact().is_some()),
                scene.output.vtk.then(|| VtkWriter::new(&vtk_dir, model)),
            ),
            Some(p) => {
                let path = dir.join("timeseries.csv");
                let rows = truncate_csv(&path, p.sim.state.time)?;
                // The rows continued must be the ones the checkpoint wrote.
                let written = &p.history.time;
                let same = |a: f64, b: f64| format!("{a:.12e}") == format!("{b:.12e}");
                if rows.len() != written.len()
                    || rows.iter().zip(written).any(|(a, b)| !same(*a, *b))
                {
                    return Err(format!(
                        "{}: {} rows up to t = {} s, but the checkpoint wrote {} (the file was \
                         changed, truncated or is another run's); start the run again \
                         (without --resume)",
                        path.display(),
                        rows.len(),
                        p.sim.state.time,
                        written.len()
                    ));
                }
                (
                    TimeSeries::append(dir),
                    (scene.output.vtk)
                        .then(|| VtkWriter::resume(&vtk_dir, model, p.vtk_frames.clone())),
                )
            }
        };
        Ok(Files {
            dir: dir.to_path_buf(),
            series: series.map_err(|e| io_err(&dir.join("timeseries.csv"), e))?,
            vtk: vtk.transpose().map_err(|e| io_err(&vtk_dir, e))?,
        })
    }

    /// A written step: a timeseries.csv row (with contact's columns when
    /// `contact` is given) and, when `frame`, a VTK frame.
    #[allow(clippy::too_many_arguments)]
    pub fn row(
        &mut self,
        model: &Model,
        s: &State,
        e: &Energies,
        iterations: usize,
        contact: Option<&ContactSample>,
        frame: bool,
    ) -> Result<(), String> {
        let p = model.node_position(&s.q, model.wire().last_node());
        let mut row = vec![
            s.time,
            p[0],
            p[1],
            p[2],
            e.kinetic,
            e.strain,
            e.gravity,
            e.total(),
            e.loads,
            iterations as f64,
        ];
        if let Some(c) = contact {
            row.extend([c.normal_force, c.max_penetration, e.contact, e.dissipated]);
        }
        row.push(s.previous.as_ref().map_or(0.0, |p| p.h));
        (self.series.row(&row)).map_err(|e| io_err(&self.dir.join("timeseries.csv"), e))?;
        if let Some(v) = self.vtk.as_mut().filter(|_| frame) {
            v.frame(s.time, (&s.q, &s.v), &s.plastic)
                .map_err(|e| io_err(&self.dir.join("vtk"), e))?;
        }
        Ok(())
    }

    /// A file this run writes as it goes that is no longer where it was
    /// opened (removed or renamed by another process while the run wrote
    /// through its open handle, whose rows then went nowhere), said as a
    /// warning for summary.json.
    pub fn lost(&self) -> Option<String> {
        let path = self.dir.join("timeseries.csv");
        (!path.exists()).then(|| {
            format!(
                "{} was removed while the run wrote it (by another process): its rows are lost; \
                 the other outputs are written; run again to have it",
                path.display()
            )
        })
    }

    /// Write `checkpoint.json` for `p` (its VTK frames are synced to disk
    /// first: the checkpoint names them).
    pub fn checkpoint(&mut self, scene: &Scene, p: &mut Progress) -> Result<(), String> {
        let dir = &self.dir;
        if let Some(v) = self.vtk.as_mut() {
            v.sync().map_err(|e| io_err(&dir.join("vtk"), e))?;
        }
        p.vtk_frames = self
            .vtk
            .as_ref()
            .map(|v| v.frames().to_vec())
            .unwrap_or_default();
        let text = serde_json::to_string(&Checkpoint::new(scene.source.clone(), p.clone())?)
            .map_err(|e| format!("checkpoint: {e}"))?;
        let path = dir.join("checkpoint.json");
        replace_file(&path, &text).map_err(|e| io_err(&path, e))
    }

    /// The end of a dynamic run: VTK's collection, supports.csv,
    /// rod_forces.csv, member_forces.csv, contact_point.csv, then the plots
    /// (rod_forces.png, member_loads.png and the run's own), drawn at once
    /// (`plots::draw`).
    #[allow(clippy::too_many_arguments)]
    pub fn finish(
        &mut self,
        scene: &Scene,
        history: &History,
        loads: &[LoadHistory],
        filtered: &[Filtered],
        members: MemberLoads<'_>,
        supports: SupportLoads<'_>,
        summary: &Summary,
    ) -> Result<(), String> {
        let dir = &self.dir;
        if let Some(v) = self.vtk.as_mut() {
            v.finish().map_err(|e| io_err(&dir.join("vtk"), e))?;
        }
        if !supports.loads.is_empty() {
            (write_supports(dir, &scene.model, supports))
                .map_err(|e| io_err(&dir.join("supports.csv"), e))?;
        }
        let mut plots: Vec<PlotJob<'_>> = Vec::new();
        if let Some(cs) = &summary.contact
            && let Some(c) = scene.model.contact()
            && !c.rods.is_empty()
        {
            // rod0, rod1, …, ground0, …: the model's rigid partners.
            let names: Vec<String> = (0..c.rods.len())
                .map(|i| c.rigid_name(i).replace(['[', ']'], ""))
                .collect();
            (write_rod_forces(dir, &names, loads, filtered))
                .map_err(|e| io_err(&dir.join("rod_forces.csv"), e))?;
            plots.push(Box::new(move || {
                super::plots::plot_rod_forces(dir, &names, loads, filtered, &cs.rigid())
            }));
        }
        if !members.0.is_empty() {
            let names: Vec<&str> = summary.beams.iter().map(|b| b.name.as_str()).collect();
            write_member_forces(dir, &names, members.0, members.1, members.2)
                .map_err(|e| io_err(&dir.join("member_forces.csv"), e))?;
            // Each member's bending resistance, where its section has one.
            let limits: Vec<Option<f64>> = (scene.model.beams.iter().skip(1))
                .map(|b| {
                    let section = &scene.model.element(b.elements.start).section;
                    ancf_core::loads::design_check::section_resistance(section).map(|r| r.moment)
                })
                .collect();
            plots.push(Box::new(move || {
                super::plots::plot_member_loads(dir, members, &limits, &summary.beams)
            }));
        }
        if !history.contact_point.is_empty() {
            (write_contact_point(dir, history))
                .map_err(|e| io_err(&dir.join("contact_point.csv"), e))?;
        }
        if scene.output.plots {
            plots.extend(super::plots::dynamic_plots(dir, &scene.model, history));
            super::plots::draw(plots)?;
        }
        Ok(())
    }
}

/// final_nodes.csv (the wire), final_nodes_NAME.csv (each frame member)
/// and summary.json; `beams` is each beam's name and nodes' twelve
/// coordinates, the wire first.
pub fn write_final(
    dir: &Path,
    beams: &[(String, Vec<[f64; 12]>)],
    summary: &Summary,
) -> Result<(), String> {
    for (i, (name, nodes)) in beams.iter().enumerate() {
        let file = if i == 0 {
            "final_nodes.csv".to_string()
        } else {
            format!("final_nodes_{name}.csv")
        };
        let path = dir.join(file);
        write_final_nodes(&path, nodes).map_err(|e| io_err(&path, e))?;
    }
    summary
        .write(dir)
        .map_err(|e| io_err(&dir.join("summary.json"), e))
}

/// `rod_forces.csv`: every step's force on each rod and ground (columns
/// `rod0_…`, `ground0_…`), |F| raw and CFC
/// filtered (interpolated from the filter's grid to the step times), and
/// the components.
fn write_rod_forces(
    out: &Path,
    names: &[String],
    loads: &[LoadHistory],
    filtered: &[Filtered],
) -> std::io::Result<()> {
    let names: Vec<&str> = names.iter().map(String::as_str).collect();
    write_forces(&out.join("rod_forces.csv"), &names, loads, filtered)
}

/// `member_forces.csv`: [`write_rod_forces`]'s columns for the wire's
/// contact force on each frame member, named by the member
/// (`NAME_force`, `NAME_filtered`, `NAME_fx`, …), and `NAME_moment`, the
/// member's largest bending moment at the step (N m; `moments`: each
/// member's (time, moment) at every observed state).
fn write_member_forces(
    out: &Path,
    names: &[&str],
    loads: &[LoadHistory],
    filtered: &[Filtered],
    moments: &[Vec<(f64, f64)>],
) -> std::io::Result<()> {
    let times = loads.first().map_or(&[][..], |h| &h.time[..]);
    let at: Vec<Vec<f64>> = moments
        .iter()
        .map(|h| {
            let mut j = 0;
            times
                .iter()
                .map(|&t| {
                    while j < h.len() && h[j].0 < t {
                        j += 1;
                    }
                    h.get(j).filter(|e| e.0 == t).map_or(0.0, |e| e.1)
                })
                .collect()
        })
        .collect();
    write_forces_with(
        &out.join("member_forces.csv"),
        names,
        loads,
        filtered,
        Some(("moment", &at)),
    )
}

/// Forces over the steps, a `NAME_force, NAME_filtered, NAME_fx, NAME_fy,
/// NAME_fz` group of columns per load.
fn write_forces(
    path: &Path,
    names: &[&str],
    loads: &[LoadHistory],
    filtered: &[Filtered],
) -> std::io::Result<()> {
    write_forces_with(path, names, loads, filtered, None)
}

/// [`write_forces`] with one more column per load, `NAME_{suffix}`, its
/// value at each step in `extra`'s rows (load by load).
fn write_forces_with(
    path: &Path,
    names: &[&str],
    loads: &[LoadHistory],
    filtered: &[Filtered],
    extra: Option<(&str, &[Vec<f64>])>,
) -> std::io::Result<()> {
    let mut s = String::from("time");
    for n in names {
        s += &format!(",{n}_force,{n}_filtered,{n}_fx,{n}_fy,{n}_fz");
        if let Some((suffix, _)) = extra {
            s += &format!(",{n}_{suffix}");
        }
    }
    s.push('\n');
    let steps = loads.first().map_or(0, |h| h.time.len());
    for k in 0..steps {
        let t = loads[0].time[k];
        s += &format!("{t:.9e}");
        for (i, (h, f)) in loads.iter().zip(filtered).enumerate() {
            let v = h.force[k];
            let mag = norm(v);
            s += &format!(
                ",{mag:.9e},{:.9e},{:.9e},{:.9e},{:.9e}",
                f.at(t),
                v[0],
                v[1],
                v[2]
            );
            if let Some((_, rows)) = extra {
                let x = rows.get(i).and_then(|r| r.get(k)).copied().unwrap_or(0.0);
                s += &format!(",{x:.9e}");
            }
        }
        s.push('\n');
    }
    std::fs::write(path, s)
}

/// The frame members' contact loads, filtered, and each member's largest
/// bending moment at every observed state (time s, N m), model order.
pub type MemberLoads<'a> = (&'a [LoadHistory], &'a [Filtered], &'a [Vec<(f64, f64)>]);

/// The supports' forces on the body over a run: at t = 0 and after every step.
#[derive(Clone, Copy)]
pub struct SupportLoads<'a> {
    /// Each support's force at t = 0, N (missing entries: zero).
    pub initial: &'a [[f64; 3]],
    /// Each support's force at every step, N.
    pub loads: &'a [LoadHistory],
    /// Each support's springs' moment at every step, N m (empty when no
    /// support has a rotational or torsional spring).
    pub moments: &'a [LoadHistory],
}

/// `supports.csv`: `time`, then per support i in the model's order
/// `s{i}_fx,s{i}_fy,s{i}_fz`, the force it exerts on the body (N), then
/// per support whose springs carry a moment `s{i}_mx,s{i}_my,s{i}_mz`
/// (N m, at the step's end); the first row is t = 0, then one row per step.
fn write_supports(
    out: &Path,
    model: &ancf_core::model::Model,
    supports: SupportLoads<'_>,
) -> std::io::Result<()> {
    let loads = supports.loads;
    // The supports whose springs carry a moment: their `s{i}_m…` columns.
    let moments: Vec<usize> = (0..supports.moments.len())
        .filter(|&i| model.moment_spring(i).is_some())
        .collect();
    let mut s = String::from("time");
    for i in 0..loads.len() {
        s += &format!(",s{i}_fx,s{i}_fy,s{i}_fz");
    }
    for i in &moments {
        s += &format!(",s{i}_mx,s{i}_my,s{i}_mz");
    }
    s.push('\n');
    let mut row =
        |t: f64, force: &dyn Fn(usize) -> [f64; 3], moment: &dyn Fn(usize) -> [f64; 3]| {
            s += &format!("{t:.9e}");
            for i in 0..loads.len() {
                let f = force(i);
                s += &format!(",{:.9e},{:.9e},{:.9e}", f[0], f[1], f[2]);
            }
            for &i in &moments {
                let m = moment(i);
                s += &format!(",{:.9e},{:.9e},{:.9e}", m[0], m[1], m[2]);
            }
            s.push('\n');
        };
    // The moments' histories start at t = 0, the forces' at the first step.
    let moment = |i: usize, k: usize| {
        supports.moments[i]
            .force
            .get(k)
            .copied()
            .unwrap_or([0.0; 3])
    };
    row(
        0.0,
        &|i| supports.initial.get(i).copied().unwrap_or([0.0; 3]),
        &|i| moment(i, 0),
    );
    let steps = loads.first().map_or(0, |h| h.time.len());
    for k in 0..steps {
        row(loads[0].time[k], &|i| loads[i].force[k], &|i| {
            moment(i, k + 1)
        });
    }
    std::fs::write(out.join("supports.csv"), s)
}

fn write_contact_point(out: &Path, h: &History) -> std::io::Result<()> {
    let mut s = String::from("time,dz,exx,eyy,ezz\n");
    for r in &h.contact_point {
        s.push_str(&format!(
            "{:.9e},{:.9e},{:.9e},{:.9e},{:.9e}\n",
            r[0], r[1], r[2], r[3], r[4]
        ));
    }
    std::fs::write(out.join("contact_point.csv"), s)
}

/// Keep the header and the rows of a CSV whose first column is ≤ `t`,
/// through [`replace_file`]: a run killed while it resumes still finds
/// every row its checkpoint names (a rewrite in place would leave the file
/// empty or cut for a moment).
fn truncate_csv(path: &Path, t: f64) -> Result<Vec<f64>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {} to continue it: {e}", path.display()))?;
    let mut kept = String::new();
    let mut times = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let time = line.split(',').next().and_then(|v| v.parse::<f64>().ok());
        if i == 0 || time.is_some_and(|x| x <= t + 1e-9 * t.abs().max(1e-300)) {
            kept.push_str(line);
            kept.push('\n');
            times.extend(time.filter(|_| i > 0));
        }
    }
    replace_file(path, &kept).map_err(|e| io_err(path, e))?;
    Ok(times)
}

/// Write `contents` to `path` through `path` + `.tmp` and a rename: a run
/// killed meanwhile leaves the old file whole, never an empty or cut one.
/// The `.tmp` file is made new (whatever stood there, a symbolic link
/// included, is removed, never written through); the rename replaces a
/// link at `path` itself, not its target.
fn replace_file(path: &Path, contents: &str) -> std::io::Result<()> {
    use std::io::Write as _;
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    match std::fs::remove_file(&tmp) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(e),
        _ => {}
    }
    let mut file = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&tmp)?;
    file.write_all(contents.as_bytes())?;
    drop(file);
    std::fs::rename(&tmp, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A symbolic link planted at the temporary's name is replaced, and
    /// its target keeps its contents.
    #[cfg(unix)]
    #[test]
    fn a_planted_link_at_the_temporary_is_not_written_through() {
        let dir = std::env::temp_dir().join(format!("ancf-replace-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let target = dir.join("victim");
        std::fs::write(&target, "keep").unwrap();
        std::os::unix::fs::symlink(&target, dir.join("checkpoint.json.tmp")).unwrap();
        replace_file(&dir.join("checkpoint.json"), "new").unwrap();
        assert_eq!(std::fs::read_to_string(&target).unwrap(), "keep");
        assert_eq!(
            std::fs::read_to_string(dir.join("checkpoint.json")).unwrap(),
            "new"
        );
        assert!(!dir.join("checkpoint.json.tmp").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The header and the rows up to t stay, later rows go, the kept rows'
    /// times come back, and no temporary file is left beside the CSV.
    #[test]
    fn truncate_csv_keeps_the_rows_up_to_t_and_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("ancf-truncate-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("timeseries.csv");
        std::fs::write(
            &path,
            "time,x\n0.0,1\n0.1,2\n0.2,3\n0.30000000000000004,4\n",
        )
        .unwrap();
        let times = truncate_csv(&path, 0.2).unwrap();
        assert_eq!(times, vec![0.0, 0.1, 0.2]);
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text, "time,x\n0.0,1\n0.1,2\n0.2,3\n");
        assert!(!dir.join("timeseries.csv.tmp").exists());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
