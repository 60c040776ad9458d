//! The progressive-refinement paper's Fig. 10 (Gamito and Maddock 2007, Section 4): a
//! procedural landscape at 800x400 refined with a region of interest. Three frames: when
//! the region is set, when it is fully refined, and the final image; their times beside
//! the optimised (overshooting) ray caster's total, as the paper reports them ("15% of
//! the total rendering time", "27%"). The region is given as a flag, set at the start of
//! a level, so the run is scripted and headless.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;
use tracer::progressive::{raycast, Caster, Engine, Options, Rect, SharedImage, Step};

/// The paper's frame size.
pub const SIZE: (u32, u32) = (800, 400);
/// The paper's times: the region set, the region done, the final image, and the
/// optimised ray caster, in seconds (2m 15.09s, 4m 0.93s, 14m 42.47s, 17m 13.26s).
pub const PAPER_S: [f64; 4] = [135.09, 240.93, 882.47, 1033.26];

/// What to run.
#[derive(Clone, Debug)]
pub struct Options10 {
    /// Image size.
    pub size: (u32, u32),
    /// The region (output pixels).
    pub roi: Rect,
    /// The level at whose start the region is set.
    pub roi_level: usize,
    /// Folder for `fig10.png` and `fig10.md`.
    pub out: PathBuf,
}

impl Options10 {
    /// 800x400, a region on the terrain in the lower middle, set at level 3.
    pub fn new(out: PathBuf) -> Self {
        Options10 {
            size: SIZE,
            roi: Rect {
                x0: 300,
                y0: 230,
                x1: 500,
                y1: 330,
            },
            roi_level: 3,
            out,
        }
    }
}

/// `WxH`.
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let bad = || format!("--size '{s}': expected WxH, e.g. 800x400");
    let (a, b) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (w, h): (u32, u32) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if w == 0 || h == 0 {
        return Err(bad());
    }
    Ok((w, h))
}

/// `X0,Y0,X1,Y1` (pixel corners, inclusive) inside a `w x h` image.
pub fn parse_roi(s: &str, w: u32, h: u32) -> Result<Rect, String> {
    let bad = || format!("--roi '{s}': expected X0,Y0,X1,Y1 (whole pixels inside {w}x{h})");
    let v: Vec<u32> = s
        .split(',')
        .map(|p| p.trim().parse().map_err(|_| bad()))
        .collect::<Result<_, _>>()?;
    if v.len() != 4 || v[0].max(v[2]) >= w || v[1].max(v[3]) >= h {
        return Err(bad());
    }
    Ok(Rect::from_corners((v[0], v[1]), (v[2], v[3])))
}

/// The measured times, seconds: region set, region done, final, ray caster.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Times10 {
    /// When the region was set.
    pub roi_set: f64,
    /// When the region was fully refined.
    pub roi_done: f64,
    /// The final image.
    pub total: f64,
    /// The overshooting ray caster over the whole image.
    pub caster: f64,
}

fn outline(img: &mut image::RgbImage, r: Rect) {
    let white = image::Rgb([255, 255, 255]);
    let (x1, y1) = (r.x1.min(img.width()) - 1, r.y1.min(img.height()) - 1);
    for x in r.x0..=x1 {
        img.put_pixel(x, r.y0, white);
        img.put_pixel(x, y1, white);
    }
    for y in r.y0..=y1 {
        img.put_pixel(r.x0, y, white);
        img.put_pixel(x1, y, white);
    }
}

/// Runs Fig. 10 and writes `fig10.png` (the three frames, top to bottom, the region
/// outlined in white as in the paper) and `fig10.md`.
pub fn run(o: &Options10) -> Result<(Times10, String), String> {
    let m = model_sources::find("landscape")?;
    let lambda = m
        .lipschitz
        .ok_or("the landscape model has no Lipschitz bound")?;
    let (w, h) = o.size;
    if o.roi.x1 > w || o.roi.y1 > h {
        return Err(format!("--roi {:?} is outside the {w}x{h} image", o.roi));
    }
    std::fs::create_dir_all(&o.out)
        .map_err(|e| format!("cannot create '{}': {e}", o.out.display()))?;
    let opts = Options::new(lambda);
    let mut e = Engine::new(m.clone(), m.domain, m.view, w, h, opts)?;
    let start = Instant::now();
    let mut frames: Vec<image::RgbImage> = Vec::new();
    let (mut roi_set, mut roi_done) = (None, None);
    let grab = |img: &SharedImage| img.to_rgb();
    loop {
        if roi_set.is_none() && e.next_level().is_some_and(|l| l >= o.roi_level) {
            e.set_roi(o.roi)?;
            roi_set = Some(start.elapsed().as_secs_f64());
            frames.push(grab(&e.image()));
        }
        match e.step() {
            Step::Done => break,
            Step::Processed {
                roi_finished: true, ..
            } if roi_done.is_none() => {
                roi_done = Some(start.elapsed().as_secs_f64());
                frames.push(grab(&e.image()));
            }
            _ => {}
        }
    }
    let total = start.elapsed().as_secs_f64();
    frames.push(grab(&e.image()));
    let t0 = Instant::now();
    raycast(
        &m,
        m.domain,
        m.view,
        w,
        h,
        lambda,
        opts.eps,
        Caster::Overshoot(tracer::search::lipschitz::DEFAULT_OVERSHOOT),
    )?;
    let caster = t0.elapsed().as_secs_f64();
    let t = Times10 {
        roi_set: roi_set.ok_or("the region was never set (--roi-level past the last level)")?,
        roi_done: roi_done.ok_or("the region never finished")?,
        total,
        caster,
    };
    // The three frames stacked, 4 pixels apart.
    let mut sheet = image::RgbImage::from_pixel(w, 3 * h + 8, image::Rgb([255, 255, 255]));
    for (k, f) in frames.iter_mut().enumerate() {
        if k < 2 {
            outline(f, o.roi);
        }
        image::imageops::replace(&mut sheet, f, 0, (k as u32 * (h + 4)) as i64);
    }
    let png = o.out.join("fig10.png");
    sheet
        .save(&png)
        .map_err(|e| format!("cannot write '{}': {e}", png.display()))?;
    let md = markdown(o, &t);
    let p = o.out.join("fig10.md");
    std::fs::write(&p, &md).map_err(|e| format!("cannot write '{}': {e}", p.display()))?;
    Ok((t, md))
}

/// The timings as Markdown, beside the paper's.
pub fn markdown(o: &Options10, t: &Times10) -> String {
    let mut s = String::new();
    let (w, h) = o.size;
    let r = o.roi;
    let _ = writeln!(
        s,
        "## Fig. 10 (Gamito and Maddock 2007): landscape at {w}x{h} with a region of interest\n\n\
         Region ({}, {})-({}, {}) set at the start of level {}; frames in `fig10.png` (top: \
         region set, middle: region done, bottom: final). Times in seconds, and as a share of \
         the final image's time; the paper's from its text (Pentium 4 at 1.2 GHz).\n",
        r.x0,
        r.y0,
        r.x1 - 1,
        r.y1 - 1,
        o.roi_level
    );
    s.push_str("| frame | seconds | share of total | paper seconds | paper share |\n");
    s.push_str("|---|--:|--:|--:|--:|\n");
    let names = [
        "region set",
        "region done",
        "final",
        "overshooting ray caster",
    ];
    let ours = [t.roi_set, t.roi_done, t.total, t.caster];
    for k in 0..4 {
        let _ = writeln!(
            s,
            "| {} | {:.3} | {:.0}% | {:.2} | {:.0}% |",
            names[k],
            ours[k],
            100.0 * ours[k] / t.total,
            PAPER_S[k],
            100.0 * PAPER_S[k] / PAPER_S[2]
        );
    }
    s
}
