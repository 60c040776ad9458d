//! The one list of arithmetics. Adding a fifth arithmetic: one new crate implementing
//! [`arith_core::Range`] and [`arith_core::Arithmetic`], plus one line in [`ArithKind`]
//! and one arm in [`with_arith!`](crate::with_arith).

use std::fmt;
use std::str::FromStr;

/// Which arithmetic to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ArithKind {
    Ia,
    Aa,
    Raa,
    Revaa,
}

impl ArithKind {
    /// Every arithmetic, in the paper's table order.
    pub const ALL: [ArithKind; 4] = [
        ArithKind::Ia,
        ArithKind::Aa,
        ArithKind::Raa,
        ArithKind::Revaa,
    ];

    /// Command-line name.
    pub fn name(self) -> &'static str {
        crate::with_arith!(self, A => <A as arith_core::Arithmetic>::NAME)
    }

    /// Label as in the paper's tables.
    pub fn label(self) -> &'static str {
        crate::with_arith!(self, A => <A as arith_core::Arithmetic>::LABEL)
    }
}

impl fmt::Display for ArithKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ArithKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        ArithKind::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| {
                let names: Vec<_> = ArithKind::ALL.iter().map(|k| k.name()).collect();
                format!(
                    "unknown arithmetic '{s}' (expected one of: {})",
                    names.join(", ")
                )
            })
    }
}

/// Runs `$body` with the type alias `$A` bound to the [`arith_core::Arithmetic`] family
/// selected by `$kind` (an [`ArithKind`]).
///
/// ```ignore
/// let name = with_arith!(kind, A => <A as arith_core::Arithmetic>::NAME);
/// ```
#[macro_export]
macro_rules! with_arith {
    ($kind:expr, $A:ident => $body:expr) => {
        match $kind {
            $crate::arith::ArithKind::Ia => {
                type $A = ::arith_ia::IaArith;
                $body
            }
            $crate::arith::ArithKind::Aa => {
                type $A = ::arith_aa::AaArith;
                $body
            }
            $crate::arith::ArithKind::Raa => {
                type $A = ::arith_raa::RaaArith;
                $body
            }
            $crate::arith::ArithKind::Revaa => {
                type $A = ::arith_revaa::RevAaArith;
                $body
            }
        }
    };
}
