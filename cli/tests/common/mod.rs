//! Helpers shared by the integration tests that open windows.

use std::process::{Command, Stdio};
use std::time::Duration;

/// Starts Xvfb on a free display, or `None` where Xvfb is not installed.
pub fn start_xvfb() -> Option<(String, std::process::Child)> {
    let have = Command::new("sh")
        .args(["-c", "command -v Xvfb"])
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !have {
        return None;
    }
    // A free display number: Xvfb exits at once when the number is taken.
    for k in 0..20 {
        let display = format!(":{}", 100 + (std::process::id() + 53 * k) % 900);
        let mut child = Command::new("Xvfb")
            .args([&display, "-screen", "0", "1280x1024x24", "-nolisten", "tcp"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start Xvfb");
        std::thread::sleep(Duration::from_millis(700));
        if child.try_wait().expect("poll Xvfb").is_none() {
            return Some((display, child));
        }
    }
    panic!("no free X display for Xvfb");
}
