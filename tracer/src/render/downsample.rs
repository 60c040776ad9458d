//! Anti-aliasing of a render: made at `aa` times the resolution, filtered down by the
//! B-spline filter of [`tracer_kit::bspline_filter`] (`tracer render --aa N`).

use super::RenderResult;
use tracer_kit::bspline_filter::Filter;

/// A render made at `aa` times the resolution, filtered down to `w x h`: colours by
/// eq. (A.1), each pixel's depth the nearest of its own `aa x aa` sub-pixels' (`+inf`
/// when they all miss) and its hit flag whether any of them hit. The counters are the
/// fine render's.
pub fn downsample_render(fine: &RenderResult, w: u32, h: u32, filter: &Filter) -> RenderResult {
    let aa = filter.aa();
    let (vw, vh) = (w * aa, h * aa);
    debug_assert_eq!((fine.width, fine.height), (vw, vh));
    let sub: Vec<[u8; 3]> = fine
        .rgb
        .chunks_exact(3)
        .map(|c| [c[0], c[1], c[2]])
        .collect();
    let rgb = filter.downsample(&sub, w, h);
    let n = w as usize * h as usize;
    let mut depth = vec![f32::INFINITY; n];
    let mut hit = vec![false; n];
    for y in 0..vh {
        for x in 0..vw {
            let (k, p) = (((y / aa) * w + x / aa) as usize, (y * vw + x) as usize);
            depth[k] = depth[k].min(fine.depth[p]);
            hit[k] |= fine.hit[p];
        }
    }
    RenderResult {
        width: w,
        height: h,
        rgb,
        depth,
        hit,
        stats: fine.stats,
    }
}
