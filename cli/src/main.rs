//! `tracer`: reliable ray casting of implicit surfaces from the command line.
//!
//! `tracer render`, `tracer range`, `tracer list`, `tracer preview`, `tracer view`,
//! `tracer mesh` (see `--help`), and
//! `tracer completions SHELL`, `tracer man` for the shell and the manual.
//! User errors print one line on stderr and exit with code 2. Ctrl-C stops `render` and
//! `preview` early: what was computed is written, and the exit code is 130.

use clap::{CommandFactory, Parser, Subcommand};
use std::process::ExitCode;
use tracer_cli::{list, manual, mesh, preview, preview_args, range, render, view};
use tracer_kit::interrupt;

#[derive(Parser, Debug)]
#[command(
    name = "tracer",
    version,
    about = "Reliable ray casting of implicit surfaces (FRep: f >= 0 inside)"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(Subcommand, Debug)]
enum Cmd {
    /// Render a model or a formula to a PNG (and optionally a depth map).
    #[command(after_long_help = model_sources::formula::SYNTAX)]
    Render(render::RenderArgs),
    /// Print the range of a formula over a box in each arithmetic.
    #[command(after_long_help = model_sources::formula::SYNTAX)]
    Range(range::RangeArgs),
    /// List the models with their domain and default view.
    List,
    /// Progressive refinement previewer (cone tracing with Lipschitz bounds or a range
    /// arithmetic).
    ///
    /// In the window: drag with the left mouse button to set a region of interest (it
    /// is refined first, outlined in white), right-click to cancel it; drag with the
    /// right button to orbit, turn the mouse wheel to zoom (each starts over); a model
    /// file is read again when it changes; Esc or closing the window stops refinement
    /// and writes --out.
    #[command(after_long_help = model_sources::formula::SYNTAX)]
    Preview(preview_args::PreviewArgs),
    /// Real-time window on the GPU renderer (a build with the `gpu` feature).
    ///
    /// The model is searched on the GPU as by `render --device gpu` whenever the view
    /// changes: drag with a mouse button or press the arrow keys to orbit, turn the wheel
    /// or press + / - to zoom, R to go back to the starting view; Esc or closing the
    /// window stops and writes the last frame to --out.
    #[command(after_long_help = model_sources::formula::SYNTAX)]
    View(view::ViewWindowArgs),
    /// Mesh a model or a formula: an octree pruned by range arithmetic, dual contouring
    /// with vertices kept in their cells; writes .obj, .ply or .stl.
    ///
    /// The mesh is closed (clipped to the domain), wound outward, one vertex per piece
    /// of surface in a cell; thin features below a cell are searched for down to
    /// --max-depth. --stats reports watertightness, manifoldness, the Euler
    /// characteristic, the share of cells whose topology is certified (Plantinga and
    /// Vegter) and self-intersecting triangle pairs.
    #[command(after_long_help = model_sources::formula::SYNTAX)]
    Mesh(mesh::MeshArgs),
    /// Print a shell completion script: bash, zsh, fish, elvish or powershell.
    Completions {
        /// The shell.
        shell: String,
    },
    /// Print the manual page (roff), e.g. `tracer man > tracer.1`.
    Man,
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let res = match &cli.cmd {
        Cmd::Render(a) => render::run_render(a),
        Cmd::Range(a) => range::run_range(a),
        Cmd::List => {
            list::run_list();
            Ok(())
        }
        Cmd::Preview(a) => {
            interrupt::install();
            preview::run_preview(a)
        }
        Cmd::View(a) => {
            interrupt::install();
            view::run_view(a)
        }
        Cmd::Mesh(a) => mesh::run_mesh(a),
        Cmd::Completions { shell } => manual::run_completions(shell, Cli::command()),
        Cmd::Man => manual::run_man(Cli::command()),
    };
    match res {
        // Stopped by Ctrl-C after writing what was computed.
        Ok(()) if interrupt::requested() => ExitCode::from(interrupt::exit_code()),
        Ok(()) => ExitCode::SUCCESS,
        Err(msg) => {
            // One line, whatever the message held.
            eprintln!("error: {}", msg.replace('\n', " "));
            ExitCode::from(2)
        }
    }
}
