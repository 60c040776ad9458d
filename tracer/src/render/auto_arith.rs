//! The default arithmetic, chosen per render by a short probe (`tracer render --arith
//! auto`, the CLI's default).
//!
//! Measured on every built-in model and fidget's four (`docs/default-arith.md`,
//! `scripts/default-arith.sh`): RevAA is the fastest or within a few percent of it on
//! most models, but on some (fidget's bear) its `min`/`max` of overlapping affine forms
//! stay loose enough to report a wall of unconfirmed hits where the surface is not
//! (13.9% of the bear's hits). Hull is never looser than RevAA or IA (its ranges are
//! the intersection of both), draws no such wall, and costs about twice RevAA per
//! evaluation. So the probe renders the view at a few hundred pixels in RevAA and Hull
//! and keeps RevAA unless its unconfirmed hits exceed Hull's by more than
//! [`WALL_SHARE`] of the hits (at least [`WALL_MIN`] pixels): a wall shows in the
//! probe (the bear's: 575 unconfirmed of 1,295 hits in RevAA, 0 in Hull) while genuine
//! unconfirmed hits (walls seen edge-on, tangent touches) appear in both.
//!
//! RevAA is probed first, and Hull only where RevAA's unconfirmed hits exceed that
//! tolerance taken over RevAA's confirmed hits (which Hull, sound, hits too, so Hull's
//! tolerance is at least that): below it no count of Hull's could make the rule pick
//! Hull. On most models the Hull probe, the costlier one (it was most of the 25 s the
//! probe took on a union of 10,000 balls), is then skipped.
//!
//! The choice rests on counts, never on timings, so the same render always picks the
//! same arithmetic. Either choice is sound: the probe only picks which enclosure is
//! used.

use super::{render_kind, RenderOptions};
use model_ir::arith::ArithKind;
use model_ir::shape::Shape;

/// Probe pixels along the longer side of the image.
pub const PROBE_SIDE: u32 = 48;
/// How many more unconfirmed hits than Hull's (as a share of the probe's hits) RevAA
/// may report before the probe takes Hull.
pub const WALL_SHARE: f64 = 0.01;
/// The least excess of unconfirmed hits that counts as a wall.
pub const WALL_MIN: u64 = 2;

/// What the probe saw and chose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Choice {
    /// The arithmetic to render in.
    pub kind: ArithKind,
    /// The probe's size.
    pub size: (u32, u32),
    /// Hits in the probe (in Hull where it was probed, else in RevAA).
    pub hits: u64,
    /// Unconfirmed hits in the probe: RevAA's, Hull's (`None`: Hull not probed).
    pub unconfirmed: (u64, Option<u64>),
}

/// The arithmetic to render `shape` with `opts` in (see the module doc). Errors as
/// [`render_kind`] does for the options.
pub fn choose<S: Shape>(shape: &S, opts: &RenderOptions) -> Result<Choice, String> {
    let long = opts.width.max(opts.height).max(1);
    let scale = (PROBE_SIDE as f64 / long as f64).min(1.0);
    let side = |n: u32| ((n as f64 * scale).round() as u32).max(1);
    let size = (side(opts.width), side(opts.height));
    let mut probe = opts.clone();
    (probe.width, probe.height) = size;
    probe.progress = None;
    probe.shadows = false;
    let tolerance = |hits: u64| ((hits as f64 * WALL_SHARE).ceil() as u64).max(WALL_MIN);
    let revaa = render_kind(ArithKind::Revaa, shape, &probe)?.stats;
    let confirmed = revaa.hits - revaa.unconfirmed;
    if revaa.unconfirmed <= tolerance(confirmed) {
        return Ok(Choice {
            kind: ArithKind::Revaa,
            size,
            hits: revaa.hits,
            unconfirmed: (revaa.unconfirmed, None),
        });
    }
    let hull = render_kind(ArithKind::Hull, shape, &probe)?.stats;
    let walls = revaa.unconfirmed > hull.unconfirmed + tolerance(hull.hits);
    Ok(Choice {
        kind: if walls {
            ArithKind::Hull
        } else {
            ArithKind::Revaa
        },
        size,
        hits: hull.hits,
        unconfirmed: (revaa.unconfirmed, Some(hull.unconfirmed)),
    })
}
