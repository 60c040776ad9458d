// RAA*'s (AF1's) product: the quadratic term and every error product go to e.
fn af_mul(a: AF, b: AF) -> AF {
    if (af_ent(a) || af_ent(b)) {
        return AF_ENTIRE;
    }
    let c = opq(a.c * b.c);
    let u = opq(a.c * b.t);
    let v = opq(a.t * b.c);
    let t = opq(u + v);
    let main = acc(
        acc(mulup(abs(a.c), b.e), mulup(abs(b.c), a.e)),
        mulup(acc(abs(a.t), a.e), acc(abs(b.t), b.e))
    );
    let rnd = acc(acc(rerr(c), rerr(u)), acc(rerr(v), rerr(t)));
    return AF(c, t, acc(main, rnd));
}
