//! `tracer completions SHELL` and `tracer man`: the shell completion scripts and the
//! manual page, both generated from the command line's definition.

/// Writes `bytes` to stdout (a closed stdout ends the process quietly, as `out!`).
fn write_stdout(bytes: &[u8]) -> Result<(), String> {
    use std::io::Write as _;
    let mut o = std::io::stdout().lock();
    match o.write_all(bytes).and_then(|()| o.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        r => r.map_err(|e| format!("cannot write to stdout: {e}")),
    }
}

/// Runs `tracer completions SHELL`: the completion script of `cmd` for the shell.
pub fn run_completions(shell: &str, mut cmd: clap::Command) -> Result<(), String> {
    use clap_complete::Shell;
    let sh = match shell.to_ascii_lowercase().as_str() {
        "bash" => Shell::Bash,
        "zsh" => Shell::Zsh,
        "fish" => Shell::Fish,
        "elvish" => Shell::Elvish,
        "powershell" => Shell::PowerShell,
        _ => {
            return Err(format!(
                "completions: unknown shell '{shell}' (bash, zsh, fish, elvish or powershell)"
            ))
        }
    };
    let mut buf = Vec::new();
    clap_complete::generate(sh, &mut cmd, "tracer", &mut buf);
    write_stdout(&buf)
}

/// Runs `tracer man`: the manual page of `cmd` (roff).
pub fn run_man(cmd: clap::Command) -> Result<(), String> {
    let mut buf = Vec::new();
    clap_mangen::Man::new(cmd)
        .render(&mut buf)
        .map_err(|e| format!("man: {e}"))?;
    // The page opens with its `.TH` title, as man(7) has it; the rendering puts the
    // definition of the apostrophe string (used only further down) before it.
    let page = String::from_utf8_lossy(&buf);
    let lines: Vec<&str> = page.lines().collect();
    let mut out = String::with_capacity(page.len() + 1);
    if let Some(k) = lines.iter().position(|l| l.starts_with(".TH")) {
        for l in std::iter::once(&lines[k])
            .chain(&lines[..k])
            .chain(&lines[k + 1..])
        {
            out.push_str(l);
            out.push('\n');
        }
    } else {
        out.push_str(&page);
    }
    write_stdout(out.as_bytes())
}
