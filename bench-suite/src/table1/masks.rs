//! Hit-mask agreement between arithmetics: a pixel that one arithmetic hits and another
//! misses is checked by sampling its ray for a sign change, which proves a root.

use super::Cell;
use model_ir::shape::Shape;
use model_sources::PaperModel;

/// Samples per ray when checking a disputed pixel for a sign change.
pub(super) const SIGN_SAMPLES: usize = 20_000;

/// Whether `f64` samples of `m` along the pixel's ray (clipped to the domain) change
/// sign: then the ray certainly has a root (the models are continuous).
pub fn ray_changes_sign(m: PaperModel, (w, h): (u32, u32), i: u32, j: u32) -> bool {
    let model = m.model();
    let cam = model_ir::camera::Camera::new(model.view, w, h);
    let (o, d) = cam.ray(i, j);
    let Some((t0, t1)) = tracer::search::ray::clip(o, d, &model.domain, 0.0) else {
        return false;
    };
    let (mut pos, mut neg) = (false, false);
    for k in 0..=SIGN_SAMPLES {
        let t = t0 + (t1 - t0) * k as f64 / SIGN_SAMPLES as f64;
        let p = o + d * t;
        let v = m.eval(p.x, p.y, p.z);
        pos |= v > 0.0;
        neg |= v < 0.0;
        if pos && neg {
            return true;
        }
    }
    false
}

/// For every pixel where the finished arithmetics disagree, checks the ray for a sign
/// change and counts, per arithmetic, missed certain roots and unconfirmed hits.
pub(super) fn classify_disagreements(
    m: PaperModel,
    size: (u32, u32),
    masks: &[Option<Vec<bool>>],
    cells: &mut [Cell],
) {
    let done: Vec<(usize, &Vec<bool>)> = masks
        .iter()
        .enumerate()
        .filter_map(|(k, v)| v.as_ref().map(|v| (k, v)))
        .collect();
    let Some(&(_, first)) = done.first() else {
        return;
    };
    for p in 0..first.len() {
        let hit = |k: &(usize, &Vec<bool>)| k.1[p];
        if done.iter().all(hit) || !done.iter().any(hit) {
            continue;
        }
        let (i, j) = ((p % size.0 as usize) as u32, (p / size.0 as usize) as u32);
        let root = ray_changes_sign(m, size, i, j);
        for &(k, mask) in &done {
            if root && !mask[p] {
                cells[k].missed_roots += 1;
            } else if !root && mask[p] {
                cells[k].unconfirmed_hits += 1;
            }
        }
    }
}
