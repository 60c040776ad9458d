// Algorithm 1 on the GPU (Section 5.3.1): the first root on a ray by subdivision without
// recursion, with argument pruning. Each depth keeps its (pruned) segment in `segs`;
// bit k of `mask` says whether the node at depth k + 1 is its parent's right half.
// Moving on from a root-free node climbs while it is a right half, then takes the
// right half of the parent's pruned segment, so pruning never loses a part of a
// segment that was not proved root-free.

struct Params {
    zero: u32,
    eps_abs: f32,
    eps_rel: f32,
    width: u32,
    height: u32,
    cell: u32,
    cells_x: u32,
    culling: u32,
    pruning: u32,
    max_iter: u32,
    normal_h: f32,
    refine: f32,
}

// One ray (or one cell's bundle): x = o + s d for s in [s0, s1], o in
// [o_mid - o_rad, o_mid + o_rad] and d in [d_mid - d_rad, d_mid + d_rad].
struct Job {
    d_mid: vec3<f32>,
    s0: f32,
    d_rad: vec3<f32>,
    s1: f32,
    o_mid: vec3<f32>,
    pad0: f32,
    o_rad: vec3<f32>,
    pad1: f32,
}

@group(0) @binding(0) var<uniform> params: Params;
@group(0) @binding(1) var<storage, read> jobs: array<Job>;
// Per pixel: depth (along the job's s), normal.
@group(0) @binding(2) var<storage, read_write> out_px: array<vec4<f32>>;
// Per pixel: status in bits 0-1 (0 miss, 1 confirmed hit, 2 unconfirmed hit, 3 culled),
// range evaluations above.
@group(0) @binding(3) var<storage, read_write> out_st: array<u32>;
// Per cell: 1 when the cell's bundle may hold a root.
@group(0) @binding(4) var<storage, read_write> cells: array<u32>;
@group(0) @binding(5) var<storage, read> cell_jobs: array<Job>;

// The range of f on [a, b] of a job's ray (from the generated `seg_range`).
struct Seg {
    lo: f32,
    hi: f32,
    // linear part c + t eps +- e over s = m + r eps, when `lin`
    c: f32,
    t: f32,
    e: f32,
    m: f32,
    r: f32,
    lin: bool,
}

// f at the point s of the ray, as a sound interval (all the job's rays).
fn point_range(j: Job, s: f32) -> IA {
    let x = ia_coord(j.o_mid.x, j.o_rad.x, j.d_mid.x, j.d_rad.x, s, s);
    let y = ia_coord(j.o_mid.y, j.o_rad.y, j.d_mid.y, j.d_rad.y, s, s);
    let z = ia_coord(j.o_mid.z, j.o_rad.z, j.d_mid.z, j.d_rad.z, s, s);
    return model_ia(x, y, z);
}

// Argument pruning (Section 4.1.2, the listing's bound fixed: tmin and tmax differ by
// the sign of the e term): a root needs |c + t eps| <= e, so eps between
// (-e - c) / t and (e - c) / t, each enclosed in interval arithmetic. Returns the
// pruned segment within [a, b]; lo > hi when it is empty.
fn prune(f: Seg, a: f32, b: f32) -> vec2<f32> {
    if (!f.lin || abs(f.t) < 1.0 / LIM) {
        return vec2<f32>(a, b);
    }
    let q0 = ia_div(ia_sub(ia_point(-f.e), ia_point(f.c)), ia_point(f.t));
    let q1 = ia_div(ia_sub(ia_point(f.e), ia_point(f.c)), ia_point(f.t));
    if (ia_ent(q0) || ia_ent(q1)) {
        return vec2<f32>(a, b);
    }
    let lo = max(min(q0.lo, q1.lo), -1.0);
    let hi = min(max(q0.hi, q1.hi), 1.0);
    if (lo > hi) {
        return vec2<f32>(1.0, 0.0);
    }
    let p0 = ia_add(ia_point(f.m), ia_mul(ia_point(f.r), ia_point(lo))).lo;
    let p1 = ia_add(ia_point(f.m), ia_mul(ia_point(f.r), ia_point(hi))).hi;
    return vec2<f32>(max(a, p0), min(b, p1));
}

fn eps_at(s: f32) -> f32 {
    return params.eps_abs + params.eps_rel * max(s, 0.0);
}

const MAX_DEPTH: u32 = 31u;

struct Hit {
    s: f32,
    status: u32,
    evals: u32,
}

fn first_root(j: Job) -> Hit {
    var segs: array<vec2<f32>, 32>;
    var mask = 0u;
    var d = 0u;
    var a = j.s0;
    var b = j.s1;
    var evals = 0u;
    if (!(a <= b)) {
        return Hit(0.0, 0u, 0u);
    }
    for (var it = 0u; it < params.max_iter; it++) {
        let f = seg_range(j, a, b);
        evals += 1u;
        var keep = f.lo <= 0.0 && f.hi >= 0.0;
        var shrunk = false;
        if (keep && params.pruning != 0u) {
            let p = prune(f, a, b);
            if (p.x > p.y) {
                keep = false;
            } else {
                shrunk = p.y - p.x < 0.5 * (b - a);
                a = p.x;
                b = p.y;
            }
        }
        if (keep) {
            let mid = 0.5 * a + 0.5 * b;
            let eps = eps_at(a);
            if (b - a <= eps) {
                // Everything before a is root-free: a sign change proved at the ends
                // (for every ray of the job) puts the first root in [a, b].
                let fa = point_range(j, a);
                let fb = point_range(j, b);
                if ((fa.hi < 0.0 && fb.lo > 0.0) || (fa.lo > 0.0 && fb.hi < 0.0)) {
                    return Hit(mid, 1u, evals);
                }
                if (b - a <= eps * params.refine) {
                    return Hit(mid, 2u, evals);
                }
            }
            if (!(mid > a && mid < b) || d == MAX_DEPTH) {
                return Hit(mid, 2u, evals);
            }
            if (!shrunk) {
                segs[d] = vec2<f32>(a, b);
                d += 1u;
                mask = mask << 1u;
                b = mid;
            }
            continue;
        }
        // [a, b] is root-free: the next node is the right half of the nearest ancestor
        // whose left half this is.
        loop {
            if (d == 0u || (mask & 1u) == 0u) {
                break;
            }
            mask = mask >> 1u;
            d -= 1u;
        }
        if (d == 0u) {
            return Hit(0.0, 0u, evals);
        }
        mask = mask | 1u;
        let p = segs[d - 1u];
        a = 0.5 * p.x + 0.5 * p.y;
        b = p.y;
    }
    // Out of iterations: nothing before a holds a root; report a as unconfirmed.
    return Hit(a, 2u, evals);
}

fn normal_at(j: Job, s: f32) -> vec3<f32> {
    let p = j.o_mid + j.d_mid * s;
    let h = max(eps_at(s), params.normal_h);
    let gx = model_pt(p.x + h, p.y, p.z) - model_pt(p.x - h, p.y, p.z);
    let gy = model_pt(p.x, p.y + h, p.z) - model_pt(p.x, p.y - h, p.z);
    let gz = model_pt(p.x, p.y, p.z + h) - model_pt(p.x, p.y, p.z - h);
    let g = vec3<f32>(gx, gy, gz);
    let l = length(g);
    if (!(l > 0.0 && l < LIM)) {
        return vec3<f32>(0.0, 0.0, 0.0);
    }
    return -g / l;
}

@compute @workgroup_size(8, 8, 1)
fn main_px(@builtin(global_invocation_id) gid: vec3<u32>) {
    if (gid.x >= params.width || gid.y >= params.height) {
        return;
    }
    let k = gid.y * params.width + gid.x;
    if (params.culling != 0u) {
        let c = (gid.y / params.cell) * params.cells_x + gid.x / params.cell;
        if (cells[c] == 0u) {
            out_px[k] = vec4<f32>(0.0, 0.0, 0.0, 0.0);
            out_st[k] = 3u;
            return;
        }
    }
    let j = jobs[k];
    let h = first_root(j);
    var n = vec3<f32>(0.0, 0.0, 0.0);
    if (h.status != 0u) {
        n = normal_at(j, h.s);
    }
    out_px[k] = vec4<f32>(h.s, n);
    out_st[k] = h.status | (h.evals << 2u);
}

// Section 5.3.2: one range over each screen cell's bundle of rays; no zero in it: none
// of the cell's pixels can hit.
@compute @workgroup_size(64, 1, 1)
fn main_cell(@builtin(global_invocation_id) gid: vec3<u32>) {
    let k = gid.x;
    if (k >= arrayLength(&cell_jobs)) {
        return;
    }
    let j = cell_jobs[k];
    let f = seg_range(j, j.s0, j.s1);
    var keep = f.lo <= 0.0 && f.hi >= 0.0;
    if (keep && params.pruning != 0u) {
        let p = prune(f, j.s0, j.s1);
        keep = p.x <= p.y;
    }
    cells[k] = select(0u, 1u, keep);
}
