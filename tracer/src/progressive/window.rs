//! The live preview window (to be written).
use super::{Engine, PreviewArgs};
use crate::shape::Shape;

/// Runs the two-thread live preview.
pub fn run_window<S: Shape + 'static>(
    _engine: Engine<S>,
    _args: &PreviewArgs,
) -> Result<(), String> {
    Err("the preview window is not available yet: use --headless".into())
}
