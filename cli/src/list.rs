//! `tracer list`: the built-in models of the registry, each with what `render` would
//! use by default.

use tracer_kit::out;

/// Runs `tracer list`: every built-in model with its description, formula, domain and
/// default view.
pub fn run_list() {
    for m in model_sources::all() {
        let v = m.view;
        let d = m.domain;
        out!("{}", m.name);
        out!("    {}", m.description);
        match m.shape.formula() {
            // One line: bindings separated by '; ' (as --expr takes them).
            Some(f) => out!("    formula {}", f.replace('\n', " ")),
            None => out!("    formula (none: uses noise, which formulas lack)"),
        }
        out!(
            "    domain {},{},{},{},{},{}",
            d.min.x,
            d.min.y,
            d.min.z,
            d.max.x,
            d.max.y,
            d.max.z
        );
        out!(
            "    view   --eye {:.3},{:.3},{:.3} --look-at {},{},{} --up {},{},{} --fov {}",
            v.eye.x,
            v.eye.y,
            v.eye.z,
            v.look_at.x,
            v.look_at.y,
            v.look_at.z,
            v.up.x,
            v.up.y,
            v.up.z,
            v.fov_deg
        );
    }
}
