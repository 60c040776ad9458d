//! The library's unit tests, one binary linked to the library the command uses, so the
//! library is not compiled a second time for them.

mod chart;
mod counter;
mod formulas;
mod gm_rows;
mod gm_table1;
mod paper;
mod scaling;
mod scenes;
mod table1;
#[cfg(feature = "gpu")]
mod table2;
mod tightness;
