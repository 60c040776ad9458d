//! The device for the GPU tests: one per test binary. Without an adapter a test is
//! skipped with a message, unless `CI` is set or a software Vulkan (lavapipe) is
//! installed: then it fails, so CI cannot pass without running the GPU tests.

use std::sync::OnceLock;
use tracer_gpu::Gpu;

static GPU: OnceLock<Option<Gpu>> = OnceLock::new();

/// Whether a missing adapter is an error here.
fn adapter_expected() -> bool {
    let ci = std::env::var("CI").is_ok_and(|v| !v.is_empty() && v != "0" && v != "false");
    let lavapipe = ["/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d"]
        .iter()
        .any(|d| {
            std::fs::read_dir(d).is_ok_and(|it| {
                it.flatten()
                    .any(|e| e.file_name().to_string_lossy().starts_with("lvp_icd"))
            })
        });
    ci || lavapipe
}

/// The shared device, or `None` (after a message) where no adapter is expected.
#[allow(dead_code)]
pub fn gpu() -> Option<&'static Gpu> {
    let g = GPU.get_or_init(|| match Gpu::new() {
        Ok(g) => {
            eprintln!("GPU tests run on {}", g.name());
            Some(g)
        }
        Err(e) => {
            if adapter_expected() {
                panic!("{e}; CI or an installed lavapipe expects one (run .ci/setup)");
            }
            eprintln!("skipped: {e} (install mesa-vulkan-drivers to run the GPU tests)");
            None
        }
    });
    g.as_ref()
}
