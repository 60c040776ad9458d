//! `bench-suite`: regenerates the paper's Table 1 and the studies past it.
//!
//! ```text
//! bench-suite table1 [--full] [--scale F] [--models a,b] [--arith a,b]
//!                    [--budget SECONDS] [--repeats N] [--culling] [--out DIR]
//! bench-suite tightness [--models a,b] [--arith ...] [--samples N] [--out DIR]
//! bench-suite scaling [--models a,b] [--arith revaa] [--base-scale F] [--steps N] [--out DIR]
//! bench-suite progressive [--size N] [--models a,b] [--layers L] [--rounds N]
//!                         [--methods a,b] [--out DIR]
//! bench-suite formulas [--formulas N] [--depth D] [--seed S] [--arith ...] [--out DIR]
//! bench-suite kernel --json [--models DIR] [--batches 64,512] [--millis MS] [--rounds N]
//! bench-suite scenes [--sizes 10,100,1000,10000] [--pixels N] [--joins max,union]
//!                     [--paper-pixels N] [--rounds N] [--budget SECONDS] [--out DIR]
//! ```

use bench_suite::{
    fig10, formulas, gm_study, gm_table1, kernel, scaling, scenes, table1, tightness,
};
use clap::{Parser, Subcommand};
use model_sources::PaperModel;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

#[derive(Parser)]
#[command(
    name = "bench-suite",
    about = "Regenerates the revised-affine paper's Table 1 and more"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// The paper's Table 1: time, operation counts and range evaluations per model and
    /// arithmetic, with the paper's numbers beside ours.
    Table1 {
        /// The paper's resolutions (default: scaled down by --scale).
        #[arg(long)]
        full: bool,
        /// Fraction of the paper's resolution per axis (ignored with --full).
        #[arg(long, default_value_t = table1::DEFAULT_SCALE)]
        scale: f64,
        /// Comma-separated model names (default: every Appendix A model).
        #[arg(long)]
        models: Option<String>,
        /// Comma-separated arithmetics (default: all of them).
        #[arg(long)]
        arith: Option<String>,
        /// Per-cell time budget in seconds (default 10, or 600 with --full).
        #[arg(long)]
        budget: Option<f64>,
        /// Interleaved rounds; the median is reported.
        #[arg(long, default_value_t = 3)]
        repeats: usize,
        /// Turn on cell culling (the paper's CPU timings have none).
        #[arg(long)]
        culling: bool,
        /// Output directory.
        #[arg(long, default_value = "bench-out")]
        out: PathBuf,
    },
    /// Mean ratio of computed range width to the sampled true range width.
    Tightness {
        #[arg(long)]
        models: Option<String>,
        #[arg(long)]
        arith: Option<String>,
        /// Random cells and segments per model and size.
        #[arg(long, default_value_t = 100)]
        samples: usize,
        #[arg(long, default_value = "bench-out")]
        out: PathBuf,
    },
    /// Random formulas over random boxes: how often each arithmetic is wider than
    /// intervals or revised affine forms, or unbounded where intervals are bounded.
    Formulas {
        /// Number of formulas (one random box each).
        #[arg(long, default_value_t = formulas::Settings::default().formulas)]
        formulas: usize,
        /// Nesting depth of the generated formulas.
        #[arg(long, default_value_t = formulas::Settings::default().depth)]
        depth: u32,
        /// Seed of the generator.
        #[arg(long, default_value_t = formulas::Settings::default().seed)]
        seed: u64,
        /// Comma-separated arithmetics (default: all of them).
        #[arg(long)]
        arith: Option<String>,
        #[arg(long, default_value = "bench-out")]
        out: PathBuf,
    },
    /// Time and range evaluations as the resolution doubles, with and without culling.
    Scaling {
        /// Comma-separated model names (default: mitchell,sphere-noise).
        #[arg(long)]
        models: Option<String>,
        /// One arithmetic.
        #[arg(long, default_value = "revaa")]
        arith: String,
        /// Scale of the first step.
        #[arg(long, default_value_t = 0.0625)]
        base_scale: f64,
        #[arg(long, default_value_t = 4)]
        steps: usize,
        /// Per-render time budget in seconds.
        #[arg(long, default_value_t = 60.0)]
        budget: f64,
        #[arg(long, default_value = "bench-out")]
        out: PathBuf,
    },
    /// The progressive-refinement paper's Table 1 (previewer vs Lipschitz ray casters:
    /// time and point evaluations) and Fig. 9 (hypertexture with L = 1..5) as a bar chart.
    Progressive {
        /// Image width and height in pixels.
        #[arg(long, default_value_t = gm_table1::DEFAULT_SIZE)]
        size: u32,
        /// Comma-separated model names (default: mitchell-gm,blobby,hypertexture-1).
        #[arg(long)]
        models: Option<String>,
        /// Fig. 9 runs the hypertexture with L = 1..=LAYERS (0: skip Fig. 9).
        #[arg(long, default_value_t = gm_table1::FIG9_LAYERS)]
        layers: u32,
        /// Timing rounds: every method once per round, in turn (rows keep the median).
        #[arg(long, default_value_t = 1)]
        rounds: u32,
        /// Comma-separated methods (default: all; see the table's method column).
        #[arg(long)]
        methods: Option<String>,
        #[arg(long, default_value = "bench-out")]
        out: PathBuf,
    },
    /// The progressive-refinement paper's Fig. 9 alone: total rendering time of the
    /// hypertexture with L = 1..LAYERS noise layers, per method, as bar charts.
    Fig9 {
        /// Image width and height in pixels.
        #[arg(long, default_value_t = gm_table1::DEFAULT_SIZE)]
        size: u32,
        /// L = 1..=LAYERS.
        #[arg(long, default_value_t = gm_table1::FIG9_LAYERS)]
        layers: u32,
        /// Timing rounds: every method once per round, in turn (rows keep the median).
        #[arg(long, default_value_t = 1)]
        rounds: u32,
        /// Comma-separated methods (default: the paper's three and the default previewer).
        #[arg(long)]
        methods: Option<String>,
        /// Output folder (the default is where the README's figure lives).
        #[arg(long, default_value = "docs/progressive")]
        out: PathBuf,
    },
    /// Cost of one tape instruction per lane of batched evaluation, by arithmetic and
    /// lane path (avx512, avx2, emulated), on fidget's bear and colonnade: one JSON
    /// object on standard output.
    Kernel {
        /// Print JSON (the only format).
        #[arg(long)]
        json: bool,
        /// Folder holding bear.vm and colonnade.vm (default: the fidget peer's models).
        #[arg(long)]
        models: Option<PathBuf>,
        /// Comma-separated lanes per batch (multiples of 4: the RevAA, RAA* and Hull packs).
        #[arg(long, default_value = "64,512")]
        batches: String,
        /// Milliseconds per configuration and round.
        #[arg(long, default_value_t = 100)]
        millis: u64,
        /// Interleaved rounds; the median is reported.
        #[arg(long, default_value_t = 3)]
        rounds: usize,
        /// Comma-separated arithmetics to measure (point, ia, revaa, raa, hull,
        /// gradient); all by default.
        #[arg(long)]
        arith: Option<String>,
    },
    /// Our Mitchell counts against the progressive-refinement paper's Table 1, one
    /// set-up factor (bound, precision, camera) changed at a time.
    GmStudy {
        /// Image width and height in pixels.
        #[arg(long, default_value_t = 400)]
        size: u32,
        #[arg(long, default_value = "bench-out")]
        out: PathBuf,
    },
    /// The progressive-refinement paper's Fig. 10: the landscape at 800x400 refined with
    /// a region of interest, headless: three frames and their times.
    Fig10 {
        /// Image size WxH.
        #[arg(long, default_value = "800x400")]
        size: String,
        /// The region X0,Y0,X1,Y1 (pixel corners, inclusive).
        #[arg(long, default_value = "300,230,499,329", allow_hyphen_values = true)]
        roi: String,
        /// The level at whose start the region is set.
        #[arg(long, default_value_t = 3)]
        roi_level: usize,
        /// Output folder (the default is where the README's figure lives).
        #[arg(long, default_value = "docs/progressive")]
        out: PathBuf,
    },
    /// Cost against model size: scenes of N balls (max and R-function unions) and the
    /// Appendix A R-function models as tapes, with and without region specialisation.
    Scenes {
        /// Comma-separated numbers of balls.
        #[arg(long, default_value = "10,100,1000,10000")]
        sizes: String,
        /// Image side of the scenes in pixels.
        #[arg(long, default_value_t = 1024)]
        pixels: u32,
        /// Joins of the balls: max, union (R-function), or both.
        #[arg(long, default_value = "max,union")]
        joins: String,
        /// Image side of the paper models in pixels (0: leave them out).
        #[arg(long, default_value_t = 320)]
        paper_pixels: u32,
        /// Arithmetic.
        #[arg(long, default_value = "revaa")]
        arith: String,
        /// Interleaved rounds; the median is reported.
        #[arg(long, default_value_t = 3)]
        rounds: usize,
        /// Per-render time budget in seconds.
        #[arg(long, default_value_t = 300.0)]
        budget: f64,
        #[arg(long, default_value = "bench-out")]
        out: PathBuf,
    },
    /// The paper's Table 2 on the GPU: frames per second for IA, RAA* and RevAA without
    /// and with culling, beside the paper's figures (needs the `gpu` feature).
    Table2 {
        /// Comma-separated model names (default: every Appendix A model).
        #[arg(long)]
        models: Option<String>,
        /// Timed frames per configuration.
        #[arg(long, default_value_t = 9)]
        frames: usize,
        /// Also measure at 1920x1080.
        #[arg(long)]
        hd: bool,
        #[arg(long, default_value = "bench-out")]
        out: PathBuf,
    },
}

fn budget(secs: f64) -> Result<Duration, String> {
    Duration::try_from_secs_f64(secs)
        .ok()
        .filter(|d| !d.is_zero())
        .ok_or_else(|| format!("--budget {secs} must be a positive number of seconds"))
}

fn write_out(dir: &PathBuf, name: &str, text: &str) -> Result<(), String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create '{}': {e}", dir.display()))?;
    let p = dir.join(name);
    std::fs::write(&p, text).map_err(|e| format!("cannot write '{}': {e}", p.display()))
}

fn run(cli: Cli) -> Result<(), String> {
    match cli.cmd {
        Cmd::Table1 {
            full,
            scale,
            models,
            arith,
            budget: b,
            repeats,
            culling,
            out,
        } => {
            let mut o = table1::Options::new(out);
            o.full = full;
            o.scale = scale;
            if let Some(m) = models {
                o.models = table1::parse_models(&m)?;
            }
            if let Some(a) = arith {
                o.kinds = table1::parse_kinds(&a)?;
            }
            let default = if full {
                table1::DEFAULT_BUDGET_FULL
            } else {
                table1::DEFAULT_BUDGET
            };
            o.budget = budget(b.unwrap_or(default))?;
            o.repeats = repeats;
            o.culling = culling;
            o.verbose = true;
            // Ctrl-C: stop, mark the unmeasured cells, write what was measured, exit 130.
            o.cancel = Some(tracer_kit::interrupt::cancel_flag());
            let report = table1::run(&o)?;
            tracer_kit::out!("{}", table1::markdown(&report));
            eprintln!(
                "wrote {}/table1.md, table1.csv, table1.png and the images",
                o.out.display()
            );
            let dis = report.disagreements();
            if !dis.is_empty() {
                eprintln!("!!! {} hit-mask disagreement(s), see above", dis.len());
            }
            Ok(())
        }
        Cmd::Formulas {
            formulas: n,
            depth,
            seed,
            arith,
            out,
        } => {
            let kinds = match arith {
                Some(a) => table1::parse_kinds(&a)?,
                None => model_ir::arith::ArithKind::ALL.to_vec(),
            };
            if n == 0 {
                return Err("--formulas must be at least 1".into());
            }
            let s = formulas::Settings {
                formulas: n,
                depth,
                seed,
            };
            let (rows, examples) = formulas::study(&kinds, &s);
            let md = formulas::report(&rows, &examples, &s);
            tracer_kit::out!("{md}");
            write_out(&out, "formulas.md", &md)
        }
        Cmd::Tightness {
            models,
            arith,
            samples,
            out,
        } => {
            let ms = match models {
                Some(m) => table1::parse_models(&m)?,
                None => PaperModel::ALL.to_vec(),
            };
            let kinds = match arith {
                Some(a) => table1::parse_kinds(&a)?,
                None => model_ir::arith::ArithKind::ALL.to_vec(),
            };
            if samples == 0 {
                return Err("--samples must be at least 1".into());
            }
            let s = tightness::Settings {
                samples,
                ..tightness::Settings::default()
            };
            let models: Vec<_> = ms.iter().map(|m| m.model()).collect();
            let md = tightness::run(&models, &kinds, &s);
            tracer_kit::out!("{md}");
            write_out(&out, "tightness.md", &md)
        }
        Cmd::Scaling {
            models,
            arith,
            base_scale,
            steps,
            budget: b,
            out,
        } => {
            let mut o = scaling::Options {
                base_scale,
                steps,
                budget: budget(b)?,
                ..Default::default()
            };
            if let Some(m) = models {
                o.models = table1::parse_models(&m)?;
            }
            o.kind = arith.parse()?;
            let pts = scaling::measure(&o)?;
            let md = scaling::markdown(&o, &pts);
            tracer_kit::out!("{md}");
            write_out(&out, "scaling.md", &md)
        }
        Cmd::Table2 {
            models,
            frames,
            hd,
            out,
        } => table2_cmd(models, frames, hd, &out),
        Cmd::Scenes {
            sizes,
            pixels,
            joins,
            paper_pixels,
            arith,
            rounds,
            budget: b,
            out,
        } => {
            let joins = joins
                .split(',')
                .map(|t| match t.trim() {
                    "max" => Ok(scenes::Join::Max),
                    "union" => Ok(scenes::Join::RUnion),
                    _ => Err(format!("--joins: '{t}' is not max or union")),
                })
                .collect::<Result<Vec<_>, _>>()?;
            let sizes = sizes
                .split(',')
                .map(|t| match t.trim().parse::<usize>() {
                    Ok(n) if n > 0 => Ok(n),
                    _ => Err(format!("--sizes: '{t}' is not a positive number of balls")),
                })
                .collect::<Result<Vec<_>, _>>()?;
            if pixels == 0 || rounds == 0 {
                return Err("--pixels and --rounds must be positive".into());
            }
            let o = scenes::Options {
                sizes,
                pixels,
                joins,
                paper_pixels,
                kind: arith.parse()?,
                rounds,
                budget: budget(b)?,
                ..Default::default()
            };
            // The scenes as files first, to render them alone (`tracer render FILE`).
            for &join in &o.joins {
                for &n in &o.sizes {
                    let name = format!("scene-{n}-{}.expr", join.name());
                    write_out(&out, &name, &scenes::scene_file(n, join, o.seed))?;
                }
            }
            let pts = scenes::run(&o, |p| {
                eprintln!("{}: {:.3} s off, {:.3} s on", p.name, p.secs[0], p.secs[1])
            })?;
            let md = scenes::markdown(&o, &pts);
            tracer_kit::out!("{md}");
            write_out(&out, "scenes.md", &md)
        }
        Cmd::Progressive {
            size,
            models,
            layers,
            rounds,
            methods,
            out,
        } => {
            let mut o = gm_table1::Options::new(out);
            o.size = size;
            o.rounds = rounds;
            if let Some(m) = methods {
                o.methods = gm_table1::parse_methods(&m)?;
            }
            if let Some(m) = models {
                o.models = gm_table1::parse_models(&m)?;
            }
            o.layers = layers;
            o.verbose = true;
            let report = gm_table1::run(&o)?;
            tracer_kit::out!("{}", gm_table1::markdown(&report));
            eprintln!(
                "wrote {}/progressive.md, progressive.csv{}",
                o.out.display(),
                if report.fig9.is_empty() {
                    ""
                } else {
                    ", fig9.csv, fig9.png, fig9-evals.png"
                }
            );
            for line in gm_table1::goal_lines(&report) {
                if line.starts_with("!!!") {
                    eprintln!("{line}");
                }
            }
            Ok(())
        }
        Cmd::Fig9 {
            size,
            layers,
            rounds,
            methods,
            out,
        } => {
            let mut o = gm_table1::Options::new(out);
            o.size = size;
            o.models = Vec::new();
            o.layers = layers.max(1);
            o.rounds = rounds;
            o.verbose = true;
            o.methods = match methods {
                Some(m) => gm_table1::parse_methods(&m)?,
                None => gm_table1::fig9_default_methods(),
            };
            let report = gm_table1::run(&o)?;
            tracer_kit::out!("{}", gm_table1::markdown(&report));
            eprintln!(
                "wrote {}/fig9.md, fig9.csv, fig9.png, fig9-evals.png",
                o.out.display()
            );
            Ok(())
        }
        Cmd::Kernel {
            json: _,
            models,
            batches,
            millis,
            rounds,
            arith,
        } => {
            let dir = models.unwrap_or_else(kernel::default_models_dir);
            let mut o = kernel::Options::new(&dir);
            o.batches = batches
                .split(',')
                .map(|b| {
                    b.trim()
                        .parse()
                        .map_err(|_| format!("--batches: '{b}' is not a whole number"))
                })
                .collect::<Result<_, _>>()?;
            o.millis = millis;
            o.rounds = rounds;
            if let Some(a) = arith {
                o.ariths = a.split(',').map(|a| a.trim().to_string()).collect();
            }
            let json = kernel::run(&o)?;
            tracer_kit::out!("{json}");
            Ok(())
        }
        Cmd::GmStudy { size, out } => {
            let m = model_sources::find("mitchell-gm")?;
            let rows = gm_study::run(&m, size)?;
            let md = gm_study::markdown(&rows, size);
            tracer_kit::out!("{md}");
            write_out(&out, "gm-study.md", &md)
        }
        Cmd::Fig10 {
            size,
            roi,
            roi_level,
            out,
        } => {
            let (w, h) = fig10::parse_size(&size)?;
            let mut o = fig10::Options10::new(out);
            o.size = (w, h);
            o.roi = fig10::parse_roi(&roi, w, h)?;
            o.roi_level = roi_level;
            let (_, md) = fig10::run(&o)?;
            tracer_kit::out!("{md}");
            eprintln!("wrote {}/fig10.png, fig10.md", o.out.display());
            Ok(())
        }
    }
}

#[cfg(feature = "gpu")]
fn table2_cmd(
    models: Option<String>,
    frames: usize,
    hd: bool,
    out: &PathBuf,
) -> Result<(), String> {
    use bench_suite::table2;
    let models = match models {
        Some(m) => table1::parse_models(&m)?,
        None => PaperModel::ALL.to_vec(),
    };
    if frames == 0 {
        return Err("--frames must be at least 1".into());
    }
    let gpu = tracer_gpu::Gpu::new()?;
    let mut rows = table2::run(&gpu, &models, (512, 512), frames)?;
    if hd {
        rows.extend(table2::run(&gpu, &models, (1920, 1080), frames)?);
    }
    let label = if gpu.is_software() {
        format!(
            "{} (software renderer: correctness only, not a GPU figure)",
            gpu.name()
        )
    } else {
        gpu.name()
    };
    let md = table2::markdown(&label, &rows);
    tracer_kit::out!("{md}");
    write_out(out, "table2.md", &md)
}

#[cfg(not(feature = "gpu"))]
fn table2_cmd(_: Option<String>, _: usize, _: bool, _: &PathBuf) -> Result<(), String> {
    Err("table2 needs the GPU renderer: cargo run --release -p bench-suite --features gpu -- table2".into())
}

fn main() -> ExitCode {
    match run(Cli::parse()) {
        Ok(()) if tracer_kit::interrupt::requested() => {
            ExitCode::from(tracer_kit::interrupt::exit_code())
        }
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
