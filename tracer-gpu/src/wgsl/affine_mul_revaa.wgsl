// RevAA's product: x1 y1 eps^2 in [0, x1 y1] is x1 y1 / 2 +- |x1 y1| / 2; the error
// parts multiply everything else.
fn af_mul(a: AF, b: AF) -> AF {
    if (af_ent(a) || af_ent(b)) {
        return AF_ENTIRE;
    }
    let p0 = opq(a.c * b.c);
    let q = opq(a.t * b.t);
    let hd = opq(0.5 * q);
    let c = opq(p0 + hd);
    let u = opq(a.c * b.t);
    let v = opq(a.t * b.c);
    let t = opq(u + v);
    let main = acc(
        acc(mulup(a.e, b.e), mulup(b.e, acc(abs(a.c), abs(a.t)))),
        acc(mulup(a.e, acc(abs(b.c), abs(b.t))), abs(hd))
    );
    let rnd = acc(acc(acc(rerr(p0), rerr(q)), acc(rerr(hd), rerr(c))), acc(acc(rerr(u), rerr(v)), rerr(t)));
    return AF(c, t, acc(main, rnd));
}
