//! The pieces of the surface inside one cell, from its corner signs (the vertex
//! clustering of Manifold Dual Contouring): one mesh vertex per piece rather than per
//! cell, so two sheets passing through one cell do not share a vertex (which would
//! pinch the mesh into a non-manifold vertex).
//!
//! On each face of the cell the surface's trace joins the crossings of the face's
//! edges in pairs: with two crossings there is one way; with four (the corners
//! alternate in sign, the ambiguous face) the face's centre decides: if it is inside,
//! the inside corners are joined across the face and the curves cut off the outside
//! corners, else the reverse. The decision depends on the face alone, so the two cells
//! sharing a face agree, and the pieces join up across cells. A piece is a class of
//! the cell's crossing edges joined through faces (a loop on the cell's boundary);
//! each loop bounds one disk of surface.

use super::grid::{edge_between, edge_corners, face_corners};

/// No piece: the edge has no sign change.
pub const NONE: u8 = u8::MAX;

/// The piece of each of the 12 edges ([`NONE`] where the edge has no sign change),
/// pieces numbered from 0 in order of their lowest edge, and the number of pieces.
/// `mask` has bit `i` set where corner `i` is inside; `centre_inside(axis, side)` says
/// whether the centre of that face is inside (asked for ambiguous faces only).
pub fn pieces(mask: u8, mut centre_inside: impl FnMut(usize, usize) -> bool) -> ([u8; 12], u8) {
    let inside = |c: usize| mask >> c & 1 == 1;
    let mut parent: [u8; 12] = core::array::from_fn(|e| e as u8);
    for axis in 0..3 {
        for side in 0..2 {
            let cs = face_corners(axis, side);
            // The face's edges in cyclic order, edge k between corners k and k + 1.
            let es: [usize; 4] = core::array::from_fn(|k| edge_between(cs[k], cs[(k + 1) % 4]));
            let changing: Vec<usize> = (0..4)
                .filter(|&k| inside(cs[k]) != inside(cs[(k + 1) % 4]))
                .collect();
            match changing.len() {
                2 => union(&mut parent, es[changing[0]], es[changing[1]]),
                4 => {
                    // Cut off the corners of the sign the centre does not have: join
                    // the two edges at each such corner (corner k: edges k - 1 and k).
                    let keep = centre_inside(axis, side);
                    for k in 0..4 {
                        if inside(cs[k]) != keep {
                            union(&mut parent, es[(k + 3) % 4], es[k]);
                        }
                    }
                }
                _ => {}
            }
        }
    }
    let mut piece = [NONE; 12];
    let mut count = 0u8;
    for e in 0..12 {
        let (a, b) = edge_corners(e);
        if inside(a) == inside(b) {
            continue;
        }
        let root = find(&mut parent, e as u8) as usize;
        if piece[root] == NONE {
            piece[root] = count;
            count += 1;
        }
        piece[e] = piece[root];
    }
    (piece, count)
}

fn find(parent: &mut [u8; 12], mut e: u8) -> u8 {
    while parent[e as usize] != e {
        parent[e as usize] = parent[parent[e as usize] as usize];
        e = parent[e as usize];
    }
    e
}

fn union(parent: &mut [u8; 12], a: usize, b: usize) {
    let (ra, rb) = (find(parent, a as u8), find(parent, b as u8));
    if ra != rb {
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_corner_is_one_piece_of_three_edges() {
        for c in 0..8 {
            let (p, n) = pieces(1 << c, |_, _| unreachable!("no ambiguous face"));
            assert_eq!(n, 1);
            assert_eq!(p.iter().filter(|&&x| x == 0).count(), 3);
            let (q, m) = pieces(!(1u8 << c), |_, _| unreachable!("no ambiguous face"));
            assert_eq!((q, m), (p, n));
        }
    }

    #[test]
    fn opposite_corners_are_two_pieces() {
        // Corners 0 and 7 inside: no face holds both, two separate pieces.
        let (p, n) = pieces(1 | 1 << 7, |_, _| unreachable!());
        assert_eq!(n, 2);
        assert_eq!(p.iter().filter(|&&x| x != NONE).count(), 6);
    }

    #[test]
    fn an_ambiguous_face_follows_its_centre() {
        // Corners 0 and 3 inside: the face z = 0 alternates.
        let mask = 1 | 1 << 3;
        let (_, apart) = pieces(mask, |_, _| false);
        let (_, joined) = pieces(mask, |_, _| true);
        assert_eq!((apart, joined), (2, 1));
    }

    #[test]
    fn a_slab_is_one_piece() {
        // Lower half (z = 0) inside.
        let (p, n) = pieces(0x0f, |_, _| unreachable!());
        assert_eq!(n, 1);
        assert_eq!(p.iter().filter(|&&x| x == 0).count(), 4);
    }
}
