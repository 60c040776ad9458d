//! Progressive refinement previewer (to be written).

/// Arguments of `tracer preview`.
#[derive(clap::Args, Debug, Clone)]
pub struct PreviewArgs {
    /// Model name (see `tracer list`).
    pub model: String,
}

/// Runs `tracer preview`.
pub fn run_preview(args: &PreviewArgs) -> Result<(), String> {
    Err(format!("preview of '{}' is not implemented yet", args.model))
}
