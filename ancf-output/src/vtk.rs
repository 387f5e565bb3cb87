//! VTK output for ParaView: a `.pvd` series of `.vtu` files. The wire is a
//! tube whose surface follows the deformed cross section (each surface point
//! is S(ξ, R cos φ, R sin φ) e), with point data displacement, velocity and
//! Green–Lagrange strain; each rod is a cylinder, written once. The `.pvd`
//! is rewritten after every frame, so it is valid even if a run stops.
//!
//! Frames are built and written on a thread of their own: the solver hands
//! over (t, q, v) and goes on with the next step (written in line, the
//! frames would cost a large part of a contact run).
//! At most `QUEUE` frames wait; a full queue makes the solver wait, so memory
//! stays bounded. [`VtkWriter::sync`] waits until every queued frame is on
//! disk (before a checkpoint names them); dropping the writer does too.
//!
//! A hand-written writer (≈ 150 lines of XML with zlib-compressed base64
//! binary arrays)
//! instead of vtkio: vtkio 0.6 pulls nom 3, quick-xml 0.22 and syn 1 with
//! future-incompatibility warnings (CRATES.md), for a format this small.

use ancf_core::element::{deformation_gradient, green_lagrange, shape_functions, shape_gradients};
use ancf_core::forces::plastic::{History, PlasticLayout};
use ancf_core::material::beam_plasticity::PlasticState;
use ancf_core::model::Model;
use ancf_core::model::contact::Rod;
use std::fmt::Write as _;
use std::path::Path;

/// Stations per element and angles around the tube.
const STATIONS: usize = 4;
const ANGLES: usize = 16;

/// Frames that may wait for the writer thread.
const QUEUE: usize = 4;

/// What the solver sends to the writer thread.
enum Job {
    Frame {
        t: f64,
        name: String,
        q: Vec<f64>,
        v: Vec<f64>,
        plastic: Vec<PlasticState>,
    },
    /// Answer on the channel once everything before is written.
    Sync(std::sync::mpsc::SyncSender<()>),
}

pub struct VtkWriter {
    /// Every frame queued so far (a checkpoint names them).
    frames: Vec<(f64, String)>,
    jobs: Option<std::sync::mpsc::SyncSender<Job>>,
    worker: Option<std::thread::JoinHandle<std::io::Result<()>>>,
}

/// Bytes per zlib block of a compressed array (vtkXMLWriter's default).
const BLOCK: usize = 1 << 15;

/// One `DataArray` in VTK's inline binary form, compressed as
/// vtkXMLWriter compresses it (`compressor="vtkZLibDataCompressor"`): the
/// little-endian values in blocks of [`BLOCK`] bytes, each zlib-deflated
/// on its own, after a header of UInt32s — the number of blocks, the block
/// size, the size of a last partial block (0 if none) and each block's
/// compressed size. Header and blocks are base64-encoded separately.
/// Fastest compression: the impact's and the span break's frames shrink
/// to about a third of the uncompressed base64 (BENCHMARKS.md), in less
/// time than writing the difference. Floats formatted as text would cost as much as the
/// simulation.
fn data_array(out: &mut String, vtk_type: &str, name: &str, components: usize, bytes: &[u8]) {
    use base64::Engine as _;
    use std::io::Write as _;
    let _ = writeln!(
        out,
        "        <DataArray type=\"{vtk_type}\" Name=\"{name}\" NumberOfComponents=\"{components}\" format=\"binary\">"
    );
    let blocks: Vec<Vec<u8>> = bytes
        .chunks(BLOCK)
        .map(|block| {
            let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::fast());
            z.write_all(block).expect("writing into memory");
            z.finish().expect("writing into memory")
        })
        .collect();
    let mut header = vec![
        blocks.len() as u32,
        BLOCK as u32,
        (bytes.len() % BLOCK) as u32,
    ];
    header.extend(blocks.iter().map(|b| b.len() as u32));
    let header: Vec<u8> = header.iter().flat_map(|v| v.to_le_bytes()).collect();
    let b64 = base64::engine::general_purpose::STANDARD;
    out.push_str("          ");
    b64.encode_string(&header, out);
    b64.encode_string(blocks.concat(), out);
    out.push('\n');
    let _ = writeln!(out, "        </DataArray>");
}

/// Point data and positions are written as Float32 (7 significant digits:
/// 0.1 µm on a 1 m wire, 1e-11 of a strain of 1e-4), which ParaView reads
/// natively; Float64 doubled the files (170 MB for the impact run's 200
/// frames) and their writing time for digits no plot shows. The run's
/// numbers in full precision are in final_nodes.csv and timeseries.csv.
fn f32_bytes(values: &[f64]) -> Vec<u8> {
    values
        .iter()
        .flat_map(|v| (*v as f32).to_le_bytes())
        .collect()
}

/// A quad surface as an unstructured grid.
fn write_vtu(
    path: &Path,
    points: &[[f64; 3]],
    quads: &[[usize; 4]],
    point_data: &[(&str, usize, Vec<f64>)],
) -> std::io::Result<()> {
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ = writeln!(
        s,
        "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\" header_type=\"UInt32\" compressor=\"vtkZLibDataCompressor\">"
    );
    let _ = writeln!(s, "  <UnstructuredGrid>");
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">",
        points.len(),
        quads.len()
    );
    let _ = writeln!(s, "      <PointData>");
    for (name, comps, values) in point_data {
        data_array(&mut s, "Float32", name, *comps, &f32_bytes(values));
    }
    let _ = writeln!(s, "      </PointData>");
    let _ = writeln!(s, "      <Points>");
    let flat: Vec<f64> = points.iter().flatten().copied().collect();
    data_array(&mut s, "Float32", "position", 3, &f32_bytes(&flat));
    let _ = writeln!(s, "      </Points>");
    let _ = writeln!(s, "      <Cells>");
    let ints =
        |v: &mut dyn Iterator<Item = i32>| -> Vec<u8> { v.flat_map(|i| i.to_le_bytes()).collect() };
    let connectivity = ints(&mut quads.iter().flatten().map(|&i| i as i32));
    data_array(&mut s, "Int32", "connectivity", 1, &connectivity);
    let offsets = ints(&mut (1..=quads.len()).map(|i| 4 * i as i32));
    data_array(&mut s, "Int32", "offsets", 1, &offsets);
    // VTK_QUAD = 9.
    data_array(&mut s, "UInt8", "types", 1, &vec![9u8; quads.len()]);
    let _ = writeln!(s, "      </Cells>");
    let _ = writeln!(s, "    </Piece>");
    let _ = writeln!(s, "  </UnstructuredGrid>");
    let _ = writeln!(s, "</VTKFile>");
    std::fs::write(path, s)
}

/// Quads joining consecutive rings of `angles` points (closed around).
fn tube_quads(rings: usize, angles: usize) -> Vec<[usize; 4]> {
    let mut quads = Vec::new();
    for r in 0..rings.saturating_sub(1) {
        for a in 0..angles {
            let b = (a + 1) % angles;
            quads.push([
                r * angles + a,
                r * angles + b,
                (r + 1) * angles + b,
                (r + 1) * angles + a,
            ]);
        }
    }
    quads
}

/// A rod's surface (a cylinder of 32 facets, `default_length` long when
/// it is endless), or a ground's: a square of that side centred on its
/// point, in its plane.
fn rod_surface(rod: &Rod, default_length: f64) -> (Vec<[f64; 3]>, Vec<[usize; 4]>) {
    let d = rod.axis;
    let (u, w) = ancf_core::model::section_frame(d);
    if rod.is_ground() {
        let half = 0.5 * default_length;
        let corner = |a: f64, b: f64| -> [f64; 3] {
            std::array::from_fn(|k| rod.center[k] + half * (a * u[k] + b * w[k]))
        };
        let points = vec![
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        ];
        return (points, vec![[0, 1, 2, 3]]);
    }
    let half = 0.5 * rod.length.unwrap_or(default_length);
    let n = 32;
    let mut points = Vec::new();
    for end in [-half, half] {
        for a in 0..n {
            let phi = 2.0 * std::f64::consts::PI * a as f64 / n as f64;
            let (c, s) = (phi.cos(), phi.sin());
            points.push(std::array::from_fn(|k| {
                rod.center[k] + end * d[k] + rod.radius * (c * u[k] + s * w[k])
            }));
        }
    }
    (points, tube_quads(2, n))
}

impl VtkWriter {
    /// Creates `dir` and writes the rods.
    pub fn new(dir: &Path, model: &Model) -> std::io::Result<Self> {
        VtkWriter::start(dir, model, Vec::new())
    }

    /// Continue a series: the rods are rewritten, `frames` (from a
    /// checkpoint) are kept and numbering continues after them.
    pub fn resume(dir: &Path, model: &Model, frames: Vec<(f64, String)>) -> std::io::Result<Self> {
        VtkWriter::start(dir, model, frames)
    }

    /// Writes the rods and starts the writer thread after `frames`.
    fn start(dir: &Path, model: &Model, frames: Vec<(f64, String)>) -> std::io::Result<Self> {
        std::fs::create_dir_all(dir)?;
        let mut rods = Vec::new();
        if let Some(c) = model.contact() {
            let wire_length = model.length();
            for (i, rod) in c.rods.iter().enumerate() {
                let name = format!("rod_{i}.vtu");
                let (points, quads) = rod_surface(rod, 2.0 * wire_length);
                write_vtu(&dir.join(&name), &points, &quads, &[])?;
                rods.push(name);
            }
        }
        let (jobs, queue) = std::sync::mpsc::sync_channel::<Job>(QUEUE);
        let (model, out) = (model.clone(), dir.to_path_buf());
        let (mut written, rod_files) = (frames.clone(), rods.clone());
        let worker = std::thread::Builder::new()
            .name("vtk-writer".into())
            .spawn(move || -> std::io::Result<()> {
                // After a failed write the thread keeps draining the queue
                // (the solver must not block) and reports the first error.
                let mut result = Ok(());
                for job in queue {
                    match job {
                        Job::Frame {
                            t,
                            name,
                            q,
                            v,
                            plastic,
                        } => {
                            written.push((t, name));
                            let name = &written[written.len() - 1].1;
                            if result.is_ok() {
                                result = write_frame(&out.join(name), &model, (&q, &v), &plastic)
                                    .and_then(|()| {
                                        std::fs::write(
                                            out.join("wire.pvd"),
                                            pvd(&written, &rod_files),
                                        )
                                    });
                            }
                        }
                        Job::Sync(done) => {
                            let _ = done.send(());
                        }
                    }
                }
                result
            })?;
        Ok(VtkWriter {
            frames,
            jobs: Some(jobs),
            worker: Some(worker),
        })
    }

    /// The frames written so far: (time, file name).
    pub fn frames(&self) -> &[(f64, String)] {
        &self.frames
    }

    /// Queues the wire at time `t` with coordinates `q`, velocities `v` and
    /// the yielding points' states `plastic` (empty: none) for writing. An
    /// error of an earlier frame's write is returned here.
    pub fn frame(
        &mut self,
        t: f64,
        (q, v): (&[f64], &[f64]),
        plastic: &[PlasticState],
    ) -> std::io::Result<()> {
        let name = format!("wire_{:06}.vtu", self.frames.len());
        self.frames.push((t, name.clone()));
        let job = Job::Frame {
            t,
            name,
            q: q.to_vec(),
            v: v.to_vec(),
            plastic: plastic.to_vec(),
        };
        match self.jobs.as_ref().map(|jobs| jobs.send(job)) {
            Some(Ok(())) => Ok(()),
            // The thread ended: it failed; its error says why.
            _ => self.finish(),
        }
    }

    /// Waits until every queued frame is written; returns the first write error.
    pub fn sync(&mut self) -> std::io::Result<()> {
        let (done, wait) = std::sync::mpsc::sync_channel(1);
        let sent = self.jobs.as_ref().map(|jobs| jobs.send(Job::Sync(done)));
        if matches!(sent, Some(Ok(()))) && wait.recv().is_ok() {
            return Ok(());
        }
        self.finish()
    }

    /// Writes what is queued, stops the thread and returns its first error.
    pub fn finish(&mut self) -> std::io::Result<()> {
        self.jobs = None;
        match self.worker.take().map(|w| w.join()) {
            None | Some(Ok(Ok(()))) => Ok(()),
            Some(Ok(Err(e))) => Err(e),
            Some(Err(_)) => Err(std::io::Error::other("the VTK writer thread panicked")),
        }
    }
}

impl Drop for VtkWriter {
    /// Every queued frame reaches the disk, also when a run stops early.
    fn drop(&mut self) {
        let _ = self.finish();
    }
}

/// The `.pvd` collection of `frames` (time, file), each with the rods.
fn pvd(frames: &[(f64, String)], rods: &[String]) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "<?xml version=\"1.0\"?>");
    let _ = writeln!(s, "<VTKFile type=\"Collection\" version=\"0.1\">");
    let _ = writeln!(s, "  <Collection>");
    for (t, f) in frames {
        let _ = writeln!(
            s,
            "    <DataSet timestep=\"{t:.9e}\" part=\"0\" file=\"{f}\"/>"
        );
        for (i, r) in rods.iter().enumerate() {
            let _ = writeln!(
                s,
                "    <DataSet timestep=\"{t:.9e}\" part=\"{}\" file=\"{r}\"/>",
                i + 1
            );
        }
    }
    let _ = writeln!(s, "  </Collection>");
    let _ = writeln!(s, "</VTKFile>");
    s
}

/// One frame of the wire and its frame members: each a tube surface with
/// displacement, velocity, Green–Lagrange strain and the section's twist
/// about the centerline (rad, [`ancf_core::math::twist`]) at its points; with
/// members, also the outer-fiber von Mises stress the section carries
/// (Pa, from the element-end resultants as in summary.json's `beams`,
/// linear along each element; the same around a ring).
fn write_frame(
    path: &Path,
    model: &Model,
    (q, v): (&[f64], &[f64]),
    plastic: &[PlasticState],
) -> std::io::Result<()> {
    use ancf_core::loads::member_load::{end_resultants, von_mises};
    let layout = PlasticLayout::of(model);
    let yielding = History::of(&layout, plastic, None);
    // A model with a yielding layer: each element's largest equivalent
    // plastic strain, drawn along it.
    let mut plastic_strain = Vec::new();
    let mut points = Vec::new();
    let mut quads = Vec::new();
    let (mut disp, mut vel, mut strain) = (Vec::new(), Vec::new(), Vec::new());
    let members = model.beams.len() > 1;
    let mut stress = Vec::new();
    let mut twist = Vec::new();
    for beam in &model.beams {
        let first = points.len();
        let radius = model.element(beam.elements.start).section.outer_radius();
        for el in beam.elements.clone() {
            let l = model.element(el).length;
            let ends: [f64; 2] = if members {
                std::array::from_fn(|end| {
                    let (n, m, t) = end_resultants(model, el, end, q, yielding);
                    von_mises(&model.element(el).section, n, m, t)
                })
            } else {
                [0.0; 2]
            };
            let element_plastic =
                (layout.element(plastic, el).iter()).fold(0.0f64, |m, p| m.max(p.equivalent));
            // The sections' twist at the element's nodes, the second taken
            // within π of the first, drawn linearly between them.
            let first_twist = model.node_twist(q, el);
            let turn = model.node_twist(q, el + 1) - first_twist;
            let turn =
                turn - 2.0 * std::f64::consts::PI * (turn / (2.0 * std::f64::consts::PI)).round();
            let e = model.element_coordinates(q, el);
            let e0 = model.element_coordinates(&model.reference, el);
            let ev = model.element_coordinates(v, el);
            for k in usize::from(el > beam.elements.start)..=STATIONS {
                let xi = k as f64 / STATIONS as f64;
                for a in 0..ANGLES {
                    let phi = 2.0 * std::f64::consts::PI * a as f64 / ANGLES as f64;
                    let (y, z) = (radius * phi.cos(), radius * phi.sin());
                    let s = shape_functions(xi, y, z, l);
                    let at = |x: &[f64; 24]| -> [f64; 3] {
                        std::array::from_fn(|c| (0..8).map(|i| s[i] * x[3 * i + c]).sum())
                    };
                    let (p, p0, pv) = (at(&e), at(&e0), at(&ev));
                    if members {
                        stress.push((1.0 - xi) * ends[0] + xi * ends[1]);
                    }
                    twist.push(first_twist + xi * turn);
                    if !layout.is_empty() {
                        plastic_strain.push(element_plastic);
                    }
                    points.push(p);
                    disp.extend((0..3).map(|c| p[c] - p0[c]));
                    vel.extend(pv);
                    let g = shape_gradients(xi, y, z, l);
                    let eps = green_lagrange(&deformation_gradient(&e, &g));
                    // VTK symmetric tensor order: xx, yy, zz, xy, yz, xz (shears as tensor components).
                    strain.extend([
                        eps[0],
                        eps[1],
                        eps[2],
                        0.5 * eps[5],
                        0.5 * eps[3],
                        0.5 * eps[4],
                    ]);
                }
            }
        }
        let rings = (points.len() - first) / ANGLES;
        quads.extend(
            tube_quads(rings, ANGLES)
                .into_iter()
                .map(|quad| quad.map(|i| i + first)),
        );
    }
    let mut fields = vec![
        ("displacement", 3, disp),
        ("velocity", 3, vel),
        ("green_lagrange_strain", 6, strain),
        ("twist", 1, twist),
    ];
    if members {
        fields.push(("von_mises_stress", 1, stress));
    }
    if !layout.is_empty() {
        fields.push(("equivalent_plastic_strain", 1, plastic_strain));
    }
    write_vtu(path, &points, &quads, &fields)
}

#[cfg(test)]
mod tests {
    use super::*;
    use base64::Engine as _;

    /// The inline binary array decodes to VTK's compression header — block
    /// count, block size, last partial block, compressed sizes — and its
    /// zlib blocks inflate to the values, bit for bit (the layout VTK's XML
    /// reader expects), over one block and over several with a partial
    /// last one and with none.
    #[test]
    fn compressed_data_array_round_trips() {
        use std::io::Read as _;
        let b64 = base64::engine::general_purpose::STANDARD;
        for n in [4, 3 * BLOCK / 4 + 5, 2 * BLOCK / 4] {
            let values: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin() * 1e3).collect();
            let mut xml = String::new();
            data_array(&mut xml, "Float32", "x", 2, &f32_bytes(&values));
            assert!(xml.contains(
                "type=\"Float32\" Name=\"x\" NumberOfComponents=\"2\" format=\"binary\""
            ));
            let encoded = xml.lines().nth(1).unwrap().trim();
            let bytes = 4 * n;
            let blocks = bytes.div_ceil(BLOCK);
            // The header on its own: 3 + blocks UInt32s, base64-padded.
            let header_chars = (4 * (3 + blocks)).div_ceil(3) * 4;
            let header = b64.decode(&encoded[..header_chars]).unwrap();
            let word = |k: usize| u32::from_le_bytes(header[4 * k..4 * k + 4].try_into().unwrap());
            assert_eq!(word(0) as usize, blocks);
            assert_eq!(word(1) as usize, BLOCK);
            assert_eq!(word(2) as usize, bytes % BLOCK);
            let data = b64.decode(&encoded[header_chars..]).unwrap();
            let mut raw = Vec::new();
            let mut at = 0;
            for k in 0..blocks {
                let size = word(3 + k) as usize;
                let mut block = Vec::new();
                flate2::read::ZlibDecoder::new(&data[at..at + size])
                    .read_to_end(&mut block)
                    .unwrap();
                let full = if k + 1 < blocks || bytes % BLOCK == 0 {
                    BLOCK
                } else {
                    bytes % BLOCK
                };
                assert_eq!(block.len(), full, "block {k} of {blocks}");
                raw.extend(block);
                at += size;
            }
            assert_eq!(at, data.len());
            let back: Vec<f32> = raw
                .chunks(4)
                .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
                .collect();
            let expected: Vec<f32> = values.iter().map(|v| *v as f32).collect();
            assert_eq!(back, expected);
        }
    }
}
