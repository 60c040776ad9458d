//! The one list of arithmetics. [`ArithKind`], [`ArithKind::ALL`], the names, the help
//! texts, the re-exports of the arithmetic crates and the dispatch
//! [`with_arith!`](crate::with_arith) are all generated from the list in
//! [`arith_list!`](crate::arith_list), so adding an arithmetic is one crate implementing
//! [`arith_core::Range`] and [`arith_core::Arithmetic`] plus one line there (and the
//! crate among the workspace's and `model-ir`'s dependencies in `Cargo.toml`).

use std::fmt;
use std::str::FromStr;

pub use arith_core;

/// `arith_list!([callback] { args })` calls
/// `callback! { args [ Variant => path::to::ArithmeticFamily, ... ] }` with every
/// arithmetic, in the papers' table order; `arith_list!(@crates [callback])` calls
/// `callback! { [ crate_name, ... ] }`. This is the one list: the enum, `ALL`, the
/// re-exports, the dispatch and every table are generated from it.
#[doc(hidden)]
#[macro_export]
macro_rules! arith_list {
    ($($request:tt)*) => {
        $crate::__arith_entries! { ($($request)*)
            Ia => arith_ia::IaArith,
            Aa => arith_aa::AaArith,
            Raa => arith_raa::RaaArith,
            Revaa => arith_revaa::RevAaArith,
            Hull => arith_hull::HullArith,
        }
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __arith_entries {
    ((@crates [$($callback:tt)*]) $($variant:ident => $krate:ident :: $family:ident,)*) => {
        $($callback)*! { [ $($krate),* ] }
    };
    (([$($callback:tt)*] { $($args:tt)* }) $($variant:ident => $krate:ident :: $family:ident,)*) => {
        $($callback)*! { $($args)* [ $($variant => $crate::arith::$krate::$family,)* ] }
    };
}

macro_rules! reexport_crates {
    ([ $($krate:ident),* ]) => {
        $(
            #[doc(no_inline)]
            pub use $krate;
        )*
    };
}
arith_list!(@crates [reexport_crates]);

macro_rules! define_kinds {
    ([ $($variant:ident => $family:path),* $(,)? ]) => {
        /// Which arithmetic to use: one variant per entry of the one list. Its doc, name
        /// and label come from the arithmetic itself ([`arith_core::Arithmetic`]).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
        pub enum ArithKind {
            $(
                #[allow(missing_docs)]
                $variant,
            )*
        }

        impl ArithKind {
            /// How many arithmetics there are.
            pub const COUNT: usize = [$(stringify!($variant)),*].len();
            /// Every arithmetic, in the papers' table order.
            pub const ALL: [ArithKind; ArithKind::COUNT] = [$(ArithKind::$variant),*];
        }
    };
}
arith_list!([define_kinds] {});

/// Runs `$body` with the type alias `$A` bound to the [`arith_core::Arithmetic`] family
/// selected by `$kind` (an [`ArithKind`]). It names the arithmetic crates through
/// this crate's re-exports, so it compiles in a crate that depends on `model-ir` (or on
/// `tracer`, which re-exports it) only.
///
/// ```
/// use model_ir::arith::ArithKind;
/// let names: Vec<&str> = ArithKind::ALL
///     .iter()
///     .map(|&k| model_ir::with_arith!(k, A => <A as model_ir::arith::arith_core::Arithmetic>::NAME))
///     .collect();
/// assert_eq!(names[0], "ia");
/// ```
#[macro_export]
macro_rules! with_arith {
    ($kind:expr, $A:ident => $body:expr) => {
        $crate::arith_list!([$crate::__with_arith_arms] { ($kind) $A ($body) })
    };
}

#[doc(hidden)]
#[macro_export]
macro_rules! __with_arith_arms {
    (($kind:expr) $A:ident ($body:expr) [ $($variant:ident => $family:path),* $(,)? ]) => {
        match $kind {
            $(
                $crate::arith::ArithKind::$variant => {
                    type $A = $family;
                    $body
                }
            )*
        }
    };
}

impl ArithKind {
    /// Command-line name (`revaa`).
    pub fn name(self) -> &'static str {
        crate::with_arith!(self, A => <A as arith_core::Arithmetic>::NAME)
    }

    /// Label as in the paper's tables (`RevAA`).
    pub fn label(self) -> &'static str {
        crate::with_arith!(self, A => <A as arith_core::Arithmetic>::LABEL)
    }

    /// The names of every arithmetic, `ia, aa, ...`, for help texts and messages.
    pub fn names() -> String {
        let names: Vec<_> = ArithKind::ALL.iter().map(|k| k.name()).collect();
        names.join(", ")
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
                format!(
                    "unknown arithmetic '{s}' (expected one of: {})",
                    ArithKind::names()
                )
            })
    }
}
