//! The paper's Table 1 (Fryazinov, Pasko, Comninos 2009, Section 6.1), typed in once so
//! our measurements can be printed beside it. Timings are seconds for all rays on a
//! Pentium 4 at 3.2 GHz in a modified POV-Ray, without cell culling.

use crate::counter::OpCounts;

/// One row of the paper's Table 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PaperRow {
    /// The paper's label.
    pub label: &'static str,
    /// Names a tracer model may carry for this row (first match wins).
    pub aliases: &'static [&'static str],
    /// Resolution in pixels.
    pub width: u32,
    /// Resolution's height in pixels.
    pub height: u32,
    /// All / Non-affine / Multiplications.
    pub ops: OpCounts,
    /// The paper's seconds in its column order ([`PAPER_COLUMNS`]); `None` where the
    /// paper only says `>50000`. Read them by arithmetic with [`PaperRow::seconds_of`].
    pub seconds: [Option<f64>; 4],
}

/// The arithmetics of the paper's columns, by their command-line names.
pub const PAPER_COLUMNS: [&str; 4] = ["ia", "aa", "raa", "revaa"];

impl PaperRow {
    /// The paper's seconds for arithmetic `k`; `None` for an arithmetic the paper has no
    /// column for, or where it only says `>50000`.
    pub fn seconds_of(&self, k: model_ir::arith::ArithKind) -> Option<f64> {
        let i = PAPER_COLUMNS.iter().position(|&n| n == k.name())?;
        self.seconds[i]
    }
}

const fn ops(all: u64, non_affine: u64, mul: u64) -> OpCounts {
    OpCounts {
        all,
        non_affine,
        mul,
    }
}

/// The paper's rows, in its order, with the readings of two rows "as printed" (the
/// paper's figures beside our literal transcriptions of its Appendix A text). Virtual
/// Shikki is our HyperFun transcription of the scene (`model-sources/data/shikki.hf`).
pub const TABLE1: &[PaperRow] = &[
    PaperRow {
        label: "Mitchell",
        aliases: &["mitchell"],
        width: 1280,
        height: 1024,
        ops: ops(19, 6, 6),
        seconds: [Some(38.0), Some(33.0), Some(7.0), Some(6.0)],
    },
    PaperRow {
        label: "Bretzel",
        aliases: &["bretzel", "pretzel"],
        width: 1280,
        height: 1024,
        ops: ops(16, 9, 9),
        seconds: [Some(25.0), Some(86.0), Some(22.0), Some(18.0)],
    },
    PaperRow {
        label: "Decocube",
        aliases: &["decocube"],
        width: 1280,
        height: 1024,
        ops: ops(30, 17, 17),
        seconds: [Some(17.0), Some(226.0), Some(19.0), Some(13.0)],
    },
    PaperRow {
        label: "CSG",
        aliases: &["csg"],
        width: 640,
        height: 480,
        ops: ops(96, 40, 32),
        seconds: [Some(126.0), Some(129.0), Some(20.0), Some(18.0)],
    },
    PaperRow {
        label: "Sphere with trimming",
        aliases: &["sphere-trim", "sphere-trimming", "trimming", "trim"],
        width: 1024,
        height: 768,
        ops: ops(142, 54, 37),
        seconds: [Some(837.0), Some(2566.0), Some(365.0), Some(285.0)],
    },
    PaperRow {
        label: "Sphere with noise",
        aliases: &["sphere-noise", "noise"],
        width: 800,
        height: 600,
        ops: ops(36, 11, 5),
        seconds: [Some(17.0), Some(51.0), Some(18.0), Some(9.0)],
    },
    PaperRow {
        label: "Sphere with noise, as printed",
        aliases: &["sphere-noise-printed"],
        width: 800,
        height: 600,
        ops: ops(36, 11, 5),
        seconds: [Some(17.0), Some(51.0), Some(18.0), Some(9.0)],
    },
    PaperRow {
        label: "CSG with blending",
        aliases: &["csg-blend", "csg-blending", "blend"],
        width: 640,
        height: 480,
        ops: ops(105, 42, 32),
        seconds: [Some(266.0), Some(72.0), Some(34.0), Some(31.0)],
    },
    PaperRow {
        label: "CSG with blending, as printed",
        aliases: &["csg-blending-printed"],
        width: 640,
        height: 480,
        ops: ops(105, 42, 32),
        seconds: [Some(266.0), Some(72.0), Some(34.0), Some(31.0)],
    },
    PaperRow {
        label: "Hair",
        aliases: &["hair"],
        width: 640,
        height: 480,
        ops: ops(88, 34, 22),
        seconds: [Some(4004.0), Some(1935.0), Some(708.0), Some(658.0)],
    },
    PaperRow {
        label: "Sphere with microstructure",
        aliases: &[
            "sphere-micro",
            "microstructure",
            "sphere-microstructure",
            "micro",
        ],
        width: 640,
        height: 480,
        ops: ops(65, 33, 22),
        seconds: [Some(1006.0), Some(1079.0), Some(328.0), Some(293.0)],
    },
    PaperRow {
        label: "Virtual Shikki",
        aliases: &["shikki", "virtual-shikki"],
        width: 320,
        height: 240,
        ops: ops(822, 306, 213),
        seconds: [Some(29244.0), None, Some(422.0), Some(390.0)],
    },
];

/// The paper row for a tracer model name: an exact alias first, then a model name that
/// contains an alias (`sphere-noise` matches `noise` only if no exact alias does).
pub fn find(model_name: &str) -> Option<&'static PaperRow> {
    let name = model_name.to_ascii_lowercase();
    TABLE1
        .iter()
        .find(|r| r.aliases.contains(&name.as_str()))
        .or_else(|| {
            // Longest alias first, so "csg-blend" is not taken for "csg".
            let mut best: Option<(&'static PaperRow, usize)> = None;
            for r in TABLE1 {
                for a in r.aliases {
                    if name.contains(a) && best.is_none_or(|(_, l)| a.len() > l) {
                        best = Some((r, a.len()));
                    }
                }
            }
            best.map(|(r, _)| r)
        })
}
