//! The paper's Table 2 on the GPU (feature `gpu`): frames per second at 512x512 for IA,
//! RAA* and RevAA without and with the culling pass, on every Appendix A model that
//! records into a GPU program, beside the paper's figures (an NVIDIA 9600, 2008), and
//! optionally at 1920x1080. A frame is the culling pass (when on) and the pixel pass,
//! from submission to completion, on rays prepared once (the camera does not move, as
//! in the paper's runs); the median of the frames is reported. The configurations are
//! run round-robin, one frame each per round, so a drifting clock affects them alike.

use model_sources::PaperModel;
use std::time::Duration;
use tracer::render::RenderOptions;
use tracer_gpu::{Gpu, GpuArith, Tracer};

/// The paper's Table 2 (fps): IA, RAA, RevAA without culling, RevAA with culling.
///
/// The paper's "Cup" is not defined in it; its row stands beside the Virtual Shikki
/// scene, whose sake set holds the cups (a larger model than one cup).
pub fn paper_fps(m: PaperModel) -> Option<[f64; 4]> {
    match m {
        PaperModel::Mitchell => Some([28.1, 90.1, 92.2, 97.4]),
        PaperModel::Bretzel => Some([83.8, 90.2, 90.2, 90.5]),
        PaperModel::Shikki => Some([0.56, 5.12, 5.95, 6.1]),
        PaperModel::Csg => Some([4.3, 14.6, 15.6, 17.2]),
        _ => None,
    }
}

/// One measured row: fps per (arithmetic, culling), in [`GpuArith::ALL`] order, without
/// then with culling.
#[derive(Clone, Debug)]
pub struct Row {
    /// Model name.
    pub model: String,
    /// Image size.
    pub size: (u32, u32),
    /// `fps[a][c]`: arithmetic `a`, culling `c` (0 off, 1 on).
    pub fps: Vec<[f64; 2]>,
    /// Hit pixels per arithmetic (without culling).
    pub hits: Vec<u64>,
}

/// Measures `models` at `size` with `frames` timed frames per configuration.
pub fn run(
    gpu: &Gpu,
    models: &[PaperModel],
    size: (u32, u32),
    frames: usize,
) -> Result<Vec<Row>, String> {
    let mut rows = Vec::new();
    for &m in models {
        let model = m.model();
        let program = match model.tape() {
            Ok(p) => p,
            Err(e) => {
                eprintln!("skipped {}: {e}", model.name);
                continue;
            }
        };
        let mut configs = Vec::new();
        let mut hits = Vec::new();
        for arith in GpuArith::ALL {
            let tracer = Tracer::new(gpu, &program, arith)?;
            for culling in [false, true] {
                let mut opts = RenderOptions::new(&model, size.0, size.1);
                opts.culling = culling;
                let (frame, _) = tracer_gpu::render::frame(&opts)?;
                let p = tracer.prepare(&frame)?;
                tracer.run(&p)?; // warm-up (pipeline creation, first touch)
                if !culling {
                    let out = tracer.read(&p)?;
                    hits.push(out.status.iter().filter(|s| s.is_hit()).count() as u64);
                }
                configs.push((arith, culling, p, Vec::<Duration>::new()));
            }
            for _ in 0..frames {
                for c in configs.iter_mut().filter(|c| c.0 == arith) {
                    let t = tracer.run(&c.2)?;
                    c.3.push(t);
                }
            }
        }
        let fps = GpuArith::ALL
            .iter()
            .map(|&a| {
                let f = |cull: bool| {
                    let c = configs
                        .iter()
                        .find(|c| c.0 == a && c.1 == cull)
                        .expect("config");
                    let mut t = c.3.clone();
                    t.sort();
                    1.0 / t[t.len() / 2].as_secs_f64().max(1e-9)
                };
                [f(false), f(true)]
            })
            .collect();
        eprintln!("measured {} at {}x{}", model.name, size.0, size.1);
        rows.push(Row {
            model: model.name.clone(),
            size,
            fps,
            hits,
        });
    }
    Ok(rows)
}

/// The rows as a Markdown table, the paper's figures beside where it has them.
pub fn markdown(device: &str, rows: &[Row]) -> String {
    let mut s = format!("GPU: {device}\n\n");
    s.push_str("| Model | Size | IA | IA+cull | RAA* | RAA*+cull | RevAA | RevAA+cull | paper IA / RAA / RevAA / RevAA+cull |\n");
    s.push_str("|---|---|---|---|---|---|---|---|---|\n");
    for r in rows {
        let paper = PaperModel::ALL
            .iter()
            .find(|m| m.name() == r.model)
            .and_then(|&m| paper_fps(m))
            .filter(|_| r.size == (512, 512))
            .map(|p| {
                let cup = if r.model == PaperModel::Shikki.name() {
                    " (Cup)"
                } else {
                    ""
                };
                format!("{} / {} / {} / {}{cup}", p[0], p[1], p[2], p[3])
            })
            .unwrap_or_else(|| "-".into());
        let cells: Vec<String> = r
            .fps
            .iter()
            .flat_map(|f| [format!("{:.2}", f[0]), format!("{:.2}", f[1])])
            .collect();
        s.push_str(&format!(
            "| {} | {}x{} | {} | {paper} |\n",
            r.model,
            r.size.0,
            r.size.1,
            cells.join(" | ")
        ));
    }
    s
}
