//! `fidget-peer MODEL.vm --size N --out img.png [--mask mask.npy] [--depth d.npy]
//! [--scale S]`:
//! renders a fidget `.vm` tape with fidget's JIT 3-D rasteriser (see [`render`]) for a
//! side-by-side comparison with our `tracer` (`scripts/peer-fidget.sh`). Prints the
//! JIT, render and shading times to stderr.

mod npy;
mod render;
mod vm_check;

use std::path::PathBuf;
use std::process::ExitCode;

const USAGE: &str = "usage: fidget-peer MODEL.vm --size N --out img.png [--mask mask.npy] \
                     [--depth depth.npy] [--scale S]";

/// Command-line arguments.
struct Args {
    model: PathBuf,
    size: u32,
    out: PathBuf,
    mask: Option<PathBuf>,
    depth: Option<PathBuf>,
    scale: f32,
}

/// The largest image side accepted (fidget holds `N^2` 16-byte pixels, 1 GiB here).
const MAX_SIZE: u32 = 8192;

fn parse_args(mut it: impl Iterator<Item = String>) -> Result<Args, String> {
    let (mut model, mut size, mut out, mut mask, mut depth) = (None, None, None, None, None);
    let mut scale = 1.0f32;
    while let Some(a) = it.next() {
        let mut value = |flag: &str| it.next().ok_or(format!("{flag} needs a value"));
        match a.as_str() {
            "--size" => {
                let v = value("--size")?;
                let n: u32 = v
                    .parse()
                    .map_err(|_| format!("--size '{v}': not a whole number"))?;
                if !(1..=MAX_SIZE).contains(&n) {
                    return Err(format!("--size {n}: must be in 1..={MAX_SIZE}"));
                }
                size = Some(n);
            }
            "--out" => out = Some(PathBuf::from(value("--out")?)),
            "--mask" => mask = Some(PathBuf::from(value("--mask")?)),
            "--depth" => depth = Some(PathBuf::from(value("--depth")?)),
            "--scale" => {
                let v = value("--scale")?;
                scale = v
                    .parse()
                    .ok()
                    .filter(|s: &f32| s.is_finite() && *s > 0.0)
                    .ok_or(format!("--scale '{v}': not a positive number"))?;
            }
            "-h" | "--help" => return Err(USAGE.to_owned()),
            f if f.starts_with('-') => return Err(format!("unknown flag '{f}'; {USAGE}")),
            m if model.is_none() => model = Some(PathBuf::from(m)),
            m => return Err(format!("unexpected argument '{m}'; {USAGE}")),
        }
    }
    Ok(Args {
        model: model.ok_or(format!("missing MODEL.vm; {USAGE}"))?,
        size: size.ok_or(format!("missing --size; {USAGE}"))?,
        out: out.ok_or(format!("missing --out; {USAGE}"))?,
        mask,
        depth,
        scale,
    })
}

fn write_png(path: &std::path::Path, n: u32, rgb: &[u8]) -> Result<(), String> {
    let file = std::fs::File::create(path).map_err(|e| e.to_string())?;
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), n, n);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut w = enc.write_header().map_err(|e| e.to_string())?;
    w.write_image_data(rgb).map_err(|e| e.to_string())
}

fn run() -> Result<(), String> {
    let a = parse_args(std::env::args().skip(1))?;
    let bytes = std::fs::read(&a.model).map_err(|e| format!("{}: {e}", a.model.display()))?;
    let text =
        String::from_utf8(bytes).map_err(|_| format!("{}: not UTF-8 text", a.model.display()))?;
    vm_check::check(&text).map_err(|e| format!("{}: {e}", a.model.display()))?;
    let r = render::render(&text, a.size, a.scale)
        .map_err(|e| format!("{}: {e}", a.model.display()))?;
    write_png(&a.out, a.size, &r.rgb).map_err(|e| format!("--out {}: {e}", a.out.display()))?;
    let n = a.size as usize;
    if let Some(m) = &a.mask {
        npy::write(m, &npy::encode_u8(n, n, &r.mask))
            .map_err(|e| format!("--mask {}: {e}", m.display()))?;
    }
    if let Some(d) = &a.depth {
        npy::write(d, &npy::encode_f32(n, n, &r.depth))
            .map_err(|e| format!("--depth {}: {e}", d.display()))?;
    }
    let hits = r.mask.iter().filter(|&&m| m == 1).count();
    eprintln!(
        "fidget-peer: {} {n}x{n}: jit {:.1} ms, render {:.1} ms, shade {:.1} ms, hits {hits} ({:.4})",
        a.model.display(),
        r.jit.as_secs_f64() * 1e3,
        r.render.as_secs_f64() * 1e3,
        r.shade.as_secs_f64() * 1e3,
        hits as f64 / r.mask.len() as f64,
        n = a.size,
    );
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("fidget-peer: error: {e}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::parse_args;

    fn args(s: &str) -> Result<super::Args, String> {
        parse_args(s.split_whitespace().map(str::to_owned))
    }

    #[test]
    fn reads_every_flag() {
        let a = args("m.vm --size 64 --out o.png --mask m.npy --depth d.npy --scale 0.5").unwrap();
        assert_eq!((a.size, a.scale), (64, 0.5));
        assert_eq!(a.model.to_str(), Some("m.vm"));
        assert_eq!(a.mask.unwrap().to_str(), Some("m.npy"));
        assert_eq!(a.depth.unwrap().to_str(), Some("d.npy"));
    }

    #[test]
    fn refuses_bad_input() {
        for (s, want) in [
            ("m.vm --size 0 --out o.png", "--size 0: must be in"),
            (
                "m.vm --size x --out o.png",
                "--size 'x': not a whole number",
            ),
            (
                "m.vm --size 8 --out o.png --scale -1",
                "--scale '-1': not a positive",
            ),
            ("m.vm --out o.png", "missing --size"),
            ("m.vm --size 8", "missing --out"),
            (
                "m.vm --size 8 --out o.png --bogus",
                "unknown flag '--bogus'",
            ),
            ("m.vm --size", "--size needs a value"),
        ] {
            let e = args(s).err().unwrap_or_default();
            assert!(e.starts_with(want), "{s}: {e}");
        }
    }
}
