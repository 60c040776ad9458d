//! The command-line contract: each user error exits with code 2 and one line on stderr;
//! a tiny render writes a valid PNG and a valid NPY depth map.

use std::path::PathBuf;
use std::process::{Command, Output};

fn tracer(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args(args)
        .output()
        .expect("run tracer")
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tracer-cli-test-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// Exit code 2, exactly one non-empty line on stderr, mentioning `needle`.
fn assert_user_error(args: &[&str], needle: &str) {
    let out = tracer(args);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: stderr {err}");
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{args:?}: expected one line, got {err:?}");
    assert!(
        lines[0].contains(needle),
        "{args:?}: '{}' does not mention '{needle}'",
        lines[0]
    );
    assert!(!err.contains("panicked"), "{args:?} panicked");
}

#[test]
fn unknown_model() {
    assert_user_error(&["render", "no-such-model"], "no-such-model");
}

#[test]
fn bad_sizes() {
    let out = tmp("size.png");
    let out = out.to_str().unwrap();
    for s in [
        "0x10", "10x0", "abc", "10x", "x10", "-3x4", "99999x10", "1.5x2",
    ] {
        assert_user_error(&["render", "csg", "--size", s, "--out", out], "--size");
    }
}

#[test]
fn bad_number_lists() {
    let out = tmp("lists.png");
    let out = out.to_str().unwrap();
    let cases: &[(&str, &str)] = &[
        ("--eye", "1,2"),
        ("--eye", "1,2,x"),
        ("--look-at", "1,2,3,4"),
        ("--up", "nan,0,1"),
        ("--domain", "-1,-1,-1,1,1"),
        ("--domain", "1,-1,-1,-1,1,1"),
        ("--fov", "abc"),
        ("--fov", "-10"),
        ("--eps", "0"),
    ];
    for (flag, v) in cases {
        assert_user_error(
            &["render", "csg", "--size", "8x8", "--out", out, flag, v],
            flag,
        );
    }
}

#[test]
fn degenerate_camera() {
    let out = tmp("cam.png");
    assert_user_error(
        &[
            "render",
            "csg",
            "--size",
            "8x8",
            "--out",
            out.to_str().unwrap(),
            "--eye",
            "0,5,0",
            "--look-at",
            "0,0,0",
        ],
        "up",
    );
}

#[test]
fn unknown_arith() {
    assert_user_error(&["render", "csg", "--arith", "quantum"], "--arith");
    assert_user_error(
        &[
            "range",
            "--expr",
            "x",
            "--box",
            "0,0,0,1,1,1",
            "--arith",
            "quantum",
        ],
        "--arith",
    );
}

#[test]
fn unwritable_outputs() {
    assert_user_error(
        &[
            "render",
            "csg",
            "--size",
            "8x8",
            "--out",
            "/nonexistent-dir-tracer/x.png",
        ],
        "--out",
    );
    let out = tmp("ok.png");
    let out = out.to_str().unwrap();
    assert_user_error(
        &[
            "render",
            "csg",
            "--size",
            "8x8",
            "--out",
            out,
            "--depth",
            "/nonexistent-dir-tracer/d.npy",
        ],
        "--depth",
    );
    assert_user_error(
        &[
            "render", "csg", "--size", "8x8", "--out", out, "--depth", "d.txt",
        ],
        "--depth",
    );
}

#[test]
fn bad_formulas() {
    let out = tmp("f.png");
    let out = out.to_str().unwrap();
    for f in ["1 +", "(x", "x ^ y", "foo(x)", ""] {
        assert_user_error(
            &["render", "--expr", f, "--size", "8x8", "--out", out],
            "--expr",
        );
        assert_user_error(&["range", "--expr", f, "--box", "0,0,0,1,1,1"], "--expr");
    }
}

#[test]
fn model_and_expr_together_or_neither() {
    assert_user_error(&["render", "csg", "--expr", "x"], "not several");
    assert_user_error(&["render"], "MODEL");
}

#[test]
fn bad_box_for_range() {
    assert_user_error(&["range", "--expr", "x", "--box", "0,0,0,1,1"], "--box");
}

#[test]
fn tiny_render_writes_png_and_npy() {
    let png = tmp("sphere.png");
    let npy = tmp("sphere.npy");
    let out = tracer(&[
        "render",
        "--expr",
        "1 - x^2 - y^2 - z^2",
        "--size",
        "20x16",
        "--out",
        png.to_str().unwrap(),
        "--depth",
        npy.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    for key in [
        "wall time",
        "rays",
        "range evaluations",
        "point evaluations",
        "cells culled",
        "range evals per hit",
    ] {
        assert!(stdout.contains(key), "stats lack '{key}': {stdout}");
    }
    let img = image::open(&png).expect("valid PNG").to_rgb8();
    assert_eq!(img.dimensions(), (20, 16));
    let b = std::fs::read(&npy).unwrap();
    assert_eq!(&b[..6], b"\x93NUMPY");
    let file = npyz::NpyFile::new(&b[..]).expect("valid NPY");
    assert_eq!(file.shape(), &[16, 20]);
    assert_eq!(file.order(), npyz::Order::C);
    let depth: Vec<f32> = file.into_vec().expect("float32 data");
    assert_eq!(depth.len(), 20 * 16);
    // The unit ball seen from the default view: hits near the centre, misses at the corners.
    let centre = depth[8 * 20 + 10];
    assert!(centre.is_finite() && centre > 0.0, "{centre}");
    assert_eq!(depth[0], f32::INFINITY);
    // Hit pixels differ in colour from the background.
    assert_ne!(img.get_pixel(10, 8), img.get_pixel(0, 0));
}

#[test]
fn range_json_encloses_the_function() {
    let out = tracer(&[
        "range",
        "--expr",
        "1 - x^2 - y^2 - z^2",
        "--box",
        "-1,-1,-1,1,1,1",
        "--json",
    ]);
    assert!(out.status.success());
    let s = String::from_utf8_lossy(&out.stdout);
    for a in model_ir::arith::ArithKind::ALL.map(|k| k.name()) {
        assert!(s.contains(&format!("\"arith\": \"{a}\"")), "{s}");
    }
    // Every bound pair must enclose the true range [-2, 1].
    let nums: Vec<f64> = s
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e'))
        .filter_map(|t| t.parse().ok())
        .collect();
    assert_eq!(nums.len(), 2 * model_ir::arith::ArithKind::COUNT, "{s}");
    for p in nums.chunks(2) {
        assert!(p[0] <= -2.0 && p[1] >= 1.0, "{p:?} in {s}");
    }
}

#[test]
fn list_names_every_paper_model() {
    let out = tracer(&["list"]);
    assert!(out.status.success());
    let s = String::from_utf8_lossy(&out.stdout);
    for m in model_sources::PaperModel::ALL {
        assert!(s.contains(m.name()), "{} missing", m.name());
    }
    assert!(s.contains("domain") && s.contains("--eye"));
}

/// A reader that closes the pipe early (`tracer list | head -1`) ends the output quietly:
/// exit 0, no panic message.
#[test]
fn closed_stdout_is_not_a_panic() {
    use std::process::Stdio;
    for args in [
        &["list"][..],
        &["range", "--expr", "x", "--box", "0,0,0,1,1,1"][..],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_tracer"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("tracer runs");
        // Close the reading end before the process writes.
        drop(child.stdout.take());
        let out = child.wait_with_output().expect("tracer ends");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{args:?}: {:?} {err}", out.status);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

/// A headless preview whose stdout is closed (`| head -1`) or full (`> /dev/full`)
/// still refines to the end and writes its image, without a panic.
#[test]
fn preview_with_a_closed_or_full_stdout_still_writes_its_image() {
    use std::process::Stdio;
    let png = tmp("closed-preview.png");
    let args = [
        "preview",
        "mitchell-gm",
        "--headless",
        "--size",
        "32x32",
        "--out",
        png.to_str().unwrap(),
    ];
    let _ = std::fs::remove_file(&png);
    let mut child = Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("tracer runs");
    drop(child.stdout.take());
    let out = child.wait_with_output().expect("tracer ends");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{:?} {err}", out.status);
    assert!(!err.contains("panicked"), "{err}");
    assert!(image::open(&png).is_ok(), "the image was not written");
    if std::path::Path::new("/dev/full").exists() {
        let _ = std::fs::remove_file(&png);
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_tracer"))
            .args(args)
            .stdout(full)
            .output()
            .expect("tracer ends");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{:?} {err}", out.status);
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(
            err.lines().filter(|l| l.contains("cannot write")).count(),
            1,
            "{err}"
        );
        assert!(image::open(&png).is_ok(), "the image was not written");
    }
}

/// Values too large to set up the view are named, not reported as a coincident eye
/// or a parallel up vector.
#[test]
fn overflowing_views_and_domains() {
    let out = tmp("overflow.png");
    let out = out.to_str().unwrap();
    let base = ["render", "mitchell", "--size", "8x8", "--out", out];
    let run = |extra: &[&str], needle: &str| {
        let args: Vec<&str> = base.iter().chain(extra).copied().collect();
        assert_user_error(&args, needle);
    };
    run(&["--eye", "1e308,1e308,1e308"], "too far");
    run(&["--eye", "1e308,1e308,1e308"], "(1e308, 1e308, 1e308)");
    run(&["--up", "1e300,1e300,0"], "too long");
    let huge = "-1e300,-1e300,-1e300,1e300,1e300,1e300";
    run(
        &["--domain", huge],
        &format!("--domain '{huge}': the box is too large"),
    );
    let big = "-3e153,-3e153,-3e153,3e153,3e153,3e153";
    assert_user_error(
        &[
            "render", "--expr", "x", "--size", "8x8", "--out", out, "--domain", big,
        ],
        &format!("--domain '{big}': the box is too large to frame a view"),
    );
    assert_user_error(
        &[
            "render", "--expr", "x", "--size", "8x8", "--out", out, "--domain", huge,
        ],
        "--domain",
    );
}

/// Only PNG colour images are written: another --out extension is refused before the
/// render, and nothing is written.
#[test]
fn out_must_be_png() {
    for name in ["o.jpg", "o.jpeg", "o.tif", "o"] {
        let out = tmp(name);
        assert_user_error(
            &[
                "render",
                "csg",
                "--size",
                "8x8",
                "--out",
                out.to_str().unwrap(),
            ],
            &format!("--out '{}': the file must end in .png", out.display()),
        );
        assert!(!out.exists(), "{name} was written");
    }
}

/// --out and --depth naming one file (also under two spellings) is refused.
#[test]
fn out_and_depth_must_differ() {
    let same = tmp("same.npy");
    let dir = same.parent().unwrap();
    let other = dir
        .join("..")
        .join(dir.file_name().unwrap())
        .join("same.npy");
    for d in [&same, &other] {
        assert_user_error(
            &[
                "render",
                "csg",
                "--size",
                "8x8",
                "--out",
                same.to_str().unwrap(),
                "--depth",
                d.to_str().unwrap(),
            ],
            &format!("--depth '{}': is the same file as --out", d.display()),
        );
    }
    assert!(!same.exists());
}

/// The EXR depth map is one float32 channel named Z holding what the NPY one holds.
#[test]
fn exr_depth_is_one_z_channel() {
    let (png, npy, exr) = (tmp("z.png"), tmp("z.npy"), tmp("z.exr"));
    for depth in [&npy, &exr] {
        let out = tracer(&[
            "render",
            "--expr",
            "1 - x^2 - y^2 - z^2",
            "--size",
            "20x16",
            "--out",
            png.to_str().unwrap(),
            "--depth",
            depth.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let b = std::fs::read(&npy).unwrap();
    let hl = u16::from_le_bytes([b[8], b[9]]) as usize;
    let want: Vec<f32> = b[10 + hl..]
        .chunks(4)
        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
        .collect();
    assert!(want.iter().any(|d| d.is_finite()) && want.contains(&f32::INFINITY));
    let img = exr::prelude::read_all_flat_layers_from_file(&exr).expect("valid EXR");
    assert_eq!(img.layer_data.len(), 1);
    let layer = &img.layer_data[0];
    assert_eq!((layer.size.0, layer.size.1), (20, 16));
    let names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    assert_eq!(names, ["Z"]);
    match &layer.channel_data.list[0].sample_data {
        exr::prelude::FlatSamples::F32(v) => assert_eq!(v, &want),
        other => panic!("not float32: {other:?}"),
    }
}

/// A formula may start with a minus, as FRep formulas often do.
#[test]
fn formulas_may_start_with_a_minus() {
    let out = tracer(&["range", "--expr", "-1", "--box", "0,0,0,1,1,1"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let text = String::from_utf8_lossy(&out.stdout);
    // Shortest round-trip decimals, one line per arithmetic of the list.
    assert!(text.lines().all(|l| l.ends_with("[-1.0, -1.0]")), "{text}");
    assert_eq!(
        text.lines().count(),
        model_ir::arith::ArithKind::COUNT,
        "{text}"
    );
    let png = tmp("minus.png");
    let out = tracer(&[
        "render",
        "--expr",
        "-(x^2 + y^2 + z^2 - 1)",
        "--size",
        "16x12",
        "--quiet",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(image::open(&png).is_ok());
}

/// Every command takes every model `tracer list` shows: `range` over the model's domain,
/// `preview` with a Lipschitz bound computed for a model that has none.
#[test]
fn range_and_preview_take_every_listed_model() {
    let out = tracer(&["range", "decocube", "--arith", "ia", "--json"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("\"arith\": \"ia\""));
    let png = tmp("preview-decocube.png");
    let out = tracer(&[
        "preview",
        "decocube",
        "--headless",
        "--width",
        "16",
        "--height",
        "16",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(image::open(&png).is_ok());
    // A formula previews too.
    let out = tracer(&[
        "preview",
        "--expr",
        "1 - x^2 - y^2 - z^2",
        "--headless",
        "--width",
        "16",
        "--height",
        "16",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    // A gradient the interval bound cannot bound: a note, and the range test instead
    // (sound without any Lipschitz bound), not a wrong image.
    let png = tmp("hair-preview.png");
    let out = tracer(&[
        "preview",
        "hair",
        "--headless",
        "--width",
        "8",
        "--height",
        "8",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("Lipschitz") && err.contains("--bound range"),
        "{err}"
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("bound range"));
    assert!(image::open(&png).is_ok());
}

/// A constant zero divisor or `ln` of a constant `<= 0` is a parse error naming the
/// operator's column: such a formula is infinite or NaN everywhere.
#[test]
fn degenerate_formulas_are_errors() {
    let out = tmp("degenerate.png");
    let out = out.to_str().unwrap();
    for (f, needle) in [
        ("1/0 - x^2", "column 2: division by zero"),
        ("x/0", "column 2: division by zero"),
        ("x/(1-1)", "column 2: division by zero"),
        ("0/0 + x", "column 2: division by zero"),
        ("ln(0) + x", "column 1: ln of the constant 0"),
    ] {
        assert_user_error(
            &["render", "--expr", f, "--size", "8x8", "--out", out],
            needle,
        );
    }
}

/// The number after `unconfirmed hits:` in a render's stats.
fn unconfirmed_of(stdout: &str) -> (u64, u64) {
    let num = |key: &str| -> u64 {
        let line = stdout
            .lines()
            .find(|l| l.starts_with(key))
            .unwrap_or_else(|| panic!("no '{key}' in {stdout}"));
        line[key.len()..].trim().parse().unwrap()
    };
    (num("unconfirmed hits:"), num("hit pixels:"))
}

/// A formula whose ranges hold 0 everywhere but which is nowhere 0 (`1/(x - x)` is
/// `+inf` at points) hits every pixel; the stats count them unconfirmed and a one-line
/// warning says so; a proper surface has no such warning.
#[test]
fn unconfirmed_hits_are_counted_and_warned_about() {
    let png = tmp("unconfirmed.png");
    let png = png.to_str().unwrap();
    let out = tracer(&[
        "render",
        "--expr",
        "1/(x - x) - y^2",
        "--size",
        "16x12",
        "--quiet",
        "--out",
        png,
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    let (unconfirmed, hits) = unconfirmed_of(&String::from_utf8_lossy(&out.stdout));
    assert!(hits > 0 && unconfirmed == hits, "{unconfirmed} of {hits}");
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(lines[0].starts_with("warning: ") && lines[0].contains("unconfirmed"));

    let out = tracer(&[
        "render",
        "--expr",
        "1 - x^2 - y^2 - z^2",
        "--size",
        "16x12",
        "--quiet",
        "--out",
        png,
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert!(out.stderr.is_empty(), "{out:?}");
    let (unconfirmed, hits) = unconfirmed_of(&String::from_utf8_lossy(&out.stdout));
    assert!(
        hits > 0 && unconfirmed * 4 <= hits,
        "{unconfirmed} of {hits}"
    );
}

/// `--help` ends with the formula language; a missing '*' is one line saying so.
#[test]
fn help_lists_the_formula_language() {
    for cmd in ["render", "range", "preview"] {
        let out = tracer(&[cmd, "--help"]);
        assert_eq!(out.status.code(), Some(0), "{out:?}");
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            text.contains(model_sources::formula::SYNTAX.trim_end()),
            "{cmd} --help: {text}"
        );
    }
    let out = tmp("product.png");
    let out = out.to_str().unwrap();
    for f in ["17x", "20(x)", "1 - 3 (x + 1)"] {
        assert_user_error(
            &["render", "--expr", f, "--size", "8x8", "--out", out],
            "a product needs '*'",
        );
    }
}

#[test]
fn completions_and_man_page() {
    let out = tracer(&["completions", "bash"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("tracer") && text.contains("render"), "{text}");
    for sh in ["zsh", "fish", "elvish", "powershell"] {
        let out = tracer(&["completions", sh]);
        assert_eq!(out.status.code(), Some(0), "{sh}: {out:?}");
        assert!(
            String::from_utf8_lossy(&out.stdout).contains("render"),
            "{sh}"
        );
    }
    assert_user_error(&["completions", "tcsh"], "unknown shell 'tcsh'");
    let out = tracer(&["man"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.starts_with(".TH"), "{}", &text[..text.len().min(200)]);
    assert!(text.contains("render"), "{text}");
}

#[test]
fn threads_flag() {
    let png = tmp("threads.png");
    let png = png.to_str().unwrap();
    for bad in ["0", "-1", "two", "1.5", "100000"] {
        assert_user_error(
            &[
                "render",
                "csg",
                "--size",
                "8x8",
                "--out",
                png,
                "--threads",
                bad,
            ],
            "--threads",
        );
        assert_user_error(
            &[
                "preview",
                "csg",
                "--headless",
                "--size",
                "8x8",
                "--threads",
                bad,
            ],
            "--threads",
        );
    }
    let out = tracer(&[
        "render",
        "csg",
        "--size",
        "16x12",
        "--quiet",
        "--out",
        png,
        "--threads",
        "2",
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
}

/// `--stats json`: one JSON object on stdout holding every counter.
#[test]
fn stats_as_json() {
    let png = tmp("json.png");
    let out = tracer(&[
        "render",
        "--expr",
        "1 - x^2 - y^2 - z^2",
        "--size",
        "16x12",
        "--quiet",
        "--stats",
        "json",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let text = String::from_utf8_lossy(&out.stdout);
    let j = text.trim();
    assert_eq!(text.lines().count(), 1, "{text}");
    assert!(j.starts_with('{') && j.ends_with('}'), "{j}");
    for key in [
        "\"width\": 16",
        "\"height\": 12",
        "\"arith\": \"auto\"",
        // A ball's tape has nothing to specialise: the default search is the paper's.
        "\"search\": \"paper\"",
        "\"wall_s\": ",
        "\"rays\": ",
        "\"shadow_rays\": ",
        "\"range_evals\": ",
        "\"range_evals_hit\": ",
        "\"cell_evals\": ",
        "\"point_evals\": ",
        "\"cells_culled\": ",
        "\"pixels_culled\": ",
        "\"pruned_empty\": ",
        "\"hits\": ",
        "\"unconfirmed\": ",
        "\"researched\": ",
        "\"tiles_hull\": ",
        "\"cut\": false",
        "\"tiles_done\": ",
        "\"tiles_total\": ",
    ] {
        assert!(j.contains(key), "no {key} in {j}");
    }
    // Balanced quotes and one level of braces: a flat object.
    assert_eq!(j.matches('"').count() % 2, 0, "{j}");
    assert_eq!(j.matches('{').count(), 1, "{j}");
    let hits: u64 = j
        .split("\"hits\": ")
        .nth(1)
        .and_then(|r| r.split([',', '}']).next())
        .and_then(|v| v.trim().parse().ok())
        .expect("hits is a number");
    assert!(hits > 0, "{j}");
    assert_user_error(
        &["render", "csg", "--size", "8x8", "--stats", "xml"],
        "--stats 'xml'",
    );
    assert_user_error(
        &["render", "csg", "--size", "8x8", "--search", "fast"],
        "--search: unknown search 'fast' (auto, slabs or paper)",
    );
}

/// `--search paper` renders the same hit pixels as the default search on a ball (no
/// root there is closer to another than the precision) and says so in its statistics.
#[test]
fn paper_search_gives_the_same_hits() {
    let hits = |search: &str| {
        let png = tmp(&format!("search-{search}.png"));
        let out = tracer(&[
            "render",
            "--expr",
            "1 - x^2 - y^2 - z^2",
            "--size",
            "64x48",
            "--quiet",
            "--stats",
            "json",
            "--search",
            search,
            "--out",
            png.to_str().unwrap(),
        ]);
        assert_eq!(out.status.code(), Some(0), "{out:?}");
        let j = String::from_utf8_lossy(&out.stdout).to_string();
        assert!(j.contains(&format!("\"search\": \"{search}\"")), "{j}");
        let n: u64 = j
            .split("\"hits\": ")
            .nth(1)
            .and_then(|r| r.split([',', '}']).next())
            .and_then(|v| v.trim().parse().ok())
            .expect("hits is a number");
        n
    };
    let slabs = hits("slabs");
    assert!(slabs > 50);
    assert_eq!(slabs, hits("paper"));
}

#[test]
fn preview_takes_size() {
    let png = tmp("preview-size.png");
    let out = tracer(&[
        "preview",
        "--expr",
        "1 - x^2 - y^2 - z^2",
        "--headless",
        "--size",
        "16x12",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let img = image::open(&png).expect("valid PNG");
    assert_eq!((img.width(), img.height()), (16, 12));
    assert_user_error(&["preview", "csg", "--headless", "--size", "0x3"], "--size");
    // --width/--height stay, but not together with --size.
    let out = tracer(&[
        "preview",
        "csg",
        "--headless",
        "--size",
        "8x8",
        "--width",
        "8",
    ]);
    assert_eq!(out.status.code(), Some(2), "{out:?}");
}

/// `tracer preview` takes the camera flags of `render`: looking away from the ball
/// leaves the image empty, and a bad value is one line naming its flag.
#[test]
fn preview_takes_the_camera_flags() {
    let shaded = |extra: &[&str]| {
        let png = tmp("preview-view.png");
        let mut args = vec![
            "preview",
            "--expr",
            "1 - x^2 - y^2 - z^2",
            "--headless",
            "--size",
            "16x16",
            "--out",
            png.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let out = tracer(&args);
        assert_eq!(out.status.code(), Some(0), "{out:?}");
        let img = image::open(&png).expect("valid PNG").to_rgb8();
        img.pixels()
            .filter(|p| p.0 != img.get_pixel(0, 0).0)
            .count()
    };
    assert!(shaded(&["--eye", "0,0,6", "--look-at", "0,0,0", "--fov", "30"]) > 50);
    assert_eq!(
        shaded(&["--eye", "0,0,6", "--look-at", "0,0,12", "--up", "0,1,0"]),
        0
    );
    assert_user_error(&["preview", "csg", "--headless", "--fov", "200"], "--fov");
    assert_user_error(&["preview", "csg", "--headless", "--eye", "1,2"], "--eye");
}

/// The previewer's output paths are checked before any work: one line naming the flag.
#[test]
fn preview_paths_are_checked_first() {
    let base = ["preview", "mitchell-gm", "--size", "16x16"];
    let with = |extra: &[&str]| -> Vec<String> {
        base.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    let run = |extra: &[&str], needle: &str| {
        let args = with(extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        assert_user_error(&args, needle);
    };
    run(&["--headless"], "--out");
    let dir = tmp("snapdir");
    std::fs::create_dir_all(&dir).unwrap();
    let file = tmp("snapfile.txt");
    std::fs::write(&file, "x").unwrap();
    run(&["--headless", "--out", dir.to_str().unwrap()], "--out");
    run(
        &["--headless", "--out", tmp("o.jpg").to_str().unwrap()],
        ".png",
    );
    run(
        &["--headless", "--out", "/no-such-folder-xyz/o.png"],
        "--out",
    );
    run(
        &["--headless", "--snapshots", file.to_str().unwrap()],
        "not a folder",
    );
    run(
        &["--snapshots", dir.to_str().unwrap(), "--stop-after", "0.1"],
        "--headless",
    );
}

#[test]
fn model_files_stdin_and_formats() {
    let f = tmp("notch.expr");
    std::fs::write(
        &f,
        "# domain: -1.2,-1.2,-1.2,1.2,1.2,1.2\n1 - x^2 - y^2 - z^2\n",
    )
    .unwrap();
    let fs = f.to_str().unwrap();
    let png = tmp("notch.png");
    let out = tracer(&[
        "render",
        fs,
        "--size",
        "24x16",
        "-q",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = tracer(&[
        "render",
        fs,
        "--size",
        "24x16",
        "-q",
        "--ortho",
        "2.5",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // --expr-file and MODEL give the same ranges; `-` reads standard input.
    let a = tracer(&["range", "--expr-file", fs, "--box", "0,0,0,1,1,1"]);
    let b = tracer(&["range", fs, "--box", "0,0,0,1,1,1"]);
    assert!(a.status.success() && a.stdout == b.stdout);
    use std::io::Write as _;
    let mut child = Command::new(env!("CARGO_BIN_EXE_tracer"))
        .args(["range", "-", "--box", "0,0,0,1,1,1"])
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(b"1 - x^2 - y^2 - z^2\n")
        .unwrap();
    let c = child.wait_with_output().unwrap();
    assert!(c.status.success() && c.stdout == a.stdout);
    // Errors: one line, exit 2, naming the argument and the path or position.
    assert_user_error(
        &["render", "/no/such/file.expr"],
        "MODEL '/no/such/file.expr'",
    );
    assert_user_error(
        &["range", "--expr-file", "/no/such.expr"],
        "--expr-file '/no/such.expr'",
    );
    assert_user_error(&["render", "model.txt"], "--format");
    assert_user_error(&["render", fs, "--format", "obj"], "--format");
    assert_user_error(
        &["render", fs, "--format", "hf"],
        "notch.expr:1:1: unexpected character '#'",
    );
    let bad = tmp("bad.vm");
    std::fs::write(&bad, "a var-x\nb atan a\n").unwrap();
    assert_user_error(
        &["range", bad.to_str().unwrap()],
        "bad.vm:2:3: fidget opcode 'atan'",
    );
    assert_user_error(&["render", fs, "--ortho", "-1"], "--ortho");
}

/// Each formula `tracer list` prints is accepted by `--expr` and is the built-in model:
/// the same interval ranges over boxes (the same operations in the same order); blobby's
/// range code skips blobs that cannot matter, so it is only parsed.
#[test]
fn listed_formulas_are_the_models() {
    let out = tracer(&["list"]);
    let text = String::from_utf8(out.stdout).unwrap();
    let mut name = "";
    let mut n = 0;
    for line in text.lines() {
        if !line.starts_with(' ') {
            name = line.trim();
            continue;
        }
        let Some(f) = line.trim().strip_prefix("formula ") else {
            continue;
        };
        if f.starts_with("(none") {
            continue;
        }
        n += 1;
        for b in ["0.1,0.2,0.3,0.4,0.5,0.6", "-1,-0.5,-0.25,0.5,0.75,0.125"] {
            let e = tracer(&["range", "--expr", f, "--box", b, "--arith", "ia"]);
            assert!(
                e.status.success(),
                "{name}: {}",
                String::from_utf8_lossy(&e.stderr)
            );
            if name != "blobby" {
                let m = tracer(&["range", name, "--box", b, "--arith", "ia"]);
                assert_eq!(e.stdout, m.stdout, "{name} over {b}");
            }
        }
    }
    assert_eq!(n, 14);
}

/// `--bound` picks how cones are cleared; a bad one is one line naming the flag. The
/// range test needs no Lipschitz bound and gives the same hit mask.
#[test]
fn preview_bound_modes_and_their_errors() {
    let png = tmp("preview-bound.png");
    let mut masks = Vec::new();
    for (bound, arith) in [
        ("lipschitz", "ia"),
        ("local", "ia"),
        ("range", "ia"),
        ("range", "aa"),
    ] {
        let out = tracer(&[
            "preview",
            "mitchell-gm",
            "--headless",
            "--size",
            "24x24",
            "--bound",
            bound,
            "--arith",
            arith,
            "--out",
            png.to_str().unwrap(),
        ]);
        assert_eq!(out.status.code(), Some(0), "{out:?}");
        assert!(String::from_utf8_lossy(&out.stdout).contains(&format!("bound {bound}")));
        let img = image::open(&png).unwrap().to_rgb8();
        let bg = tracer::render::shade::BACKGROUND;
        masks.push(img.pixels().map(|p| p.0 != bg).collect::<Vec<bool>>());
    }
    assert!(
        masks.iter().all(|m| m == &masks[0]),
        "the bound modes' silhouettes differ"
    );
    assert_user_error(
        &[
            "preview",
            "csg",
            "--headless",
            "--bound",
            "cone",
            "--out",
            png.to_str().unwrap(),
        ],
        "--bound",
    );
    assert_user_error(
        &[
            "preview",
            "csg",
            "--headless",
            "--bound",
            "range",
            "--arith",
            "nope",
            "--out",
            png.to_str().unwrap(),
        ],
        "--arith",
    );
    assert_user_error(
        &[
            "preview",
            "csg",
            "--headless",
            "--filter",
            "gauss",
            "--aa",
            "2",
            "--out",
            png.to_str().unwrap(),
        ],
        "--filter",
    );
}

/// A prime image size still refines progressively: several levels are reported.
#[test]
fn preview_at_a_prime_size_has_several_levels() {
    let png = tmp("preview-prime.png");
    let out = tracer(&[
        "preview",
        "mitchell-gm",
        "--headless",
        "--size",
        "67x61",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("padded"), "{text}");
    assert!(text.matches("complete:").count() >= 3, "{text}");
    assert_eq!(image::open(&png).unwrap().to_rgb8().dimensions(), (67, 61));
}

/// `--roi` headless: the region's frames are written when it is set and when it is done.
#[test]
fn preview_roi_flag_writes_its_frames() {
    let dir = tmp("roi-snaps");
    let _ = std::fs::remove_dir_all(&dir);
    let out = tracer(&[
        "preview",
        "hypertexture-1",
        "--headless",
        "--size",
        "64x32",
        "--roi",
        "10,5,30,20",
        "--roi-level",
        "2",
        "--snapshots",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("roi set at level 2") && text.contains("roi done"),
        "{text}"
    );
    for f in ["roi-set.png", "roi-done.png", "final.png"] {
        assert!(dir.join(f).exists(), "{f}");
    }
    assert_user_error(
        &[
            "preview",
            "csg",
            "--headless",
            "--size",
            "16x16",
            "--roi",
            "0,0,16,3",
            "--snapshots",
            dir.to_str().unwrap(),
        ],
        "--roi",
    );
}

/// `render --aa N` filters N x N rays per pixel into the requested size.
#[test]
fn render_aa_filters_to_the_requested_size() {
    let png = tmp("render-aa.png");
    let out = tracer(&[
        "render",
        "mitchell",
        "--size",
        "20x12",
        "--aa",
        "3",
        "--filter",
        "cubic",
        "-q",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    assert_eq!(image::open(&png).unwrap().to_rgb8().dimensions(), (20, 12));
    assert_user_error(
        &[
            "render",
            "mitchell",
            "--size",
            "20x12",
            "--aa",
            "0",
            "--out",
            png.to_str().unwrap(),
        ],
        "--aa",
    );
}

#[test]
fn view_refuses_bad_flags_before_opening_anything() {
    let missing = tmp("no-such-dir").join("v.png");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["view", "mitchell", "--arith", "aa"], "--arith"),
        (vec!["view", "mitchell", "--size", "0x10"], "--size"),
        (vec!["view", "mitchell", "--ortho", "-2"], "--ortho"),
        (vec!["view", "mitchell", "--fps", "0"], "--fps"),
        (vec!["view", "no-such-model"], "no-such-model"),
        (
            vec!["view", "mitchell", "--out", missing.to_str().unwrap()],
            "no-such-dir",
        ),
    ];
    for (args, needle) in cases {
        // Without the GPU renderer every one says so instead.
        let needle = if cfg!(feature = "gpu") {
            needle
        } else {
            "without the GPU renderer"
        };
        assert_user_error(&args, needle);
    }
}

/// `tracer mesh` refuses before any work, each with one line: a bad extension, an
/// unwritable place, bad depths, a depth beyond the machine's memory, bad flags.
#[test]
fn mesh_refusals() {
    let sphere = ["mesh", "--expr", "1 - x^2 - y^2 - z^2"];
    let with = |extra: &[&str]| -> Vec<String> {
        sphere.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    let ok_out = tmp("refused.stl");
    let ok_out = ok_out.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["--out", "x.png"], "--out"),
        (&["--out", "x"], "--out"),
        (&["--out", "/nonexistent-dir-tracer/m.obj"], "--out"),
        (&["--out", ok_out, "--depth", "1"], "--depth"),
        (&["--out", ok_out, "--depth", "x"], "--depth"),
        (&["--out", ok_out, "--depth", "-3"], "--depth"),
        (&["--out", ok_out, "--depth", "20"], "--depth 20"),
        (
            &["--out", ok_out, "--depth", "5", "--max-depth", "4"],
            "--max-depth",
        ),
        (&["--out", ok_out, "--arith", "nope"], "--arith"),
        (&["--out", ok_out, "--stats", "xml"], "--stats"),
        (&["--out", ok_out, "--threads", "0"], "--threads"),
        (&["--out", ok_out, "--domain", "1,1,1,0,0,0"], "--domain"),
    ];
    for (extra, needle) in cases {
        let args = with(extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        assert_user_error(&args, needle);
    }
    assert!(
        !std::path::Path::new(ok_out).exists(),
        "a refusal wrote a file"
    );
    let dir = std::env::temp_dir();
    assert_user_error(&["mesh", "no-such-model", "--out", ok_out], "no-such-model");
    assert_user_error(&["mesh", "csg", "--out", dir.to_str().unwrap()], "--out");
}

/// Each format is written and reads back as the same closed mesh: OBJ and PLY
/// indexed (V - E + F = 2 for a sphere), STL with the same triangle count.
#[test]
fn mesh_writes_each_format() {
    let mut triangles = Vec::new();
    for ext in ["obj", "ply", "stl"] {
        let path = tmp(&format!("sphere.{ext}"));
        let out = tracer(&[
            "mesh",
            "--expr",
            "0.5 - x^2 - y^2 - z^2",
            "--domain",
            "-1,-1,-1,1,1,1",
            "--depth",
            "4",
            "--out",
            path.to_str().unwrap(),
            "--stats",
            "json",
        ]);
        assert_eq!(out.status.code(), Some(0), "{out:?}");
        let json = String::from_utf8_lossy(&out.stdout);
        assert_eq!(json.lines().count(), 1, "{json}");
        for key in [
            "\"watertight\": true",
            "\"manifold\": true",
            "\"euler\": 2",
            "\"self_intersections\": 0",
        ] {
            assert!(json.contains(key), "{key} not in {json}");
        }
        let bytes = std::fs::read(&path).unwrap();
        let (v, f) = match ext {
            "obj" => {
                let text = String::from_utf8(bytes).unwrap();
                let v = text.lines().filter(|l| l.starts_with("v ")).count();
                let f: Vec<[usize; 3]> = text
                    .lines()
                    .filter_map(|l| l.strip_prefix("f "))
                    .map(|l| {
                        let i: Vec<usize> = l.split(' ').map(|x| x.parse().unwrap()).collect();
                        [i[0], i[1], i[2]]
                    })
                    .collect();
                assert!(f.iter().flatten().all(|&i| (1..=v).contains(&i)));
                (v, f.len())
            }
            "ply" => {
                let end = bytes
                    .windows(11)
                    .position(|w| w == b"end_header\n")
                    .unwrap()
                    + 11;
                let header = String::from_utf8_lossy(&bytes[..end]).to_string();
                let count = |what: &str| -> usize {
                    header
                        .lines()
                        .find_map(|l| l.strip_prefix(&format!("element {what} ")))
                        .unwrap()
                        .parse()
                        .unwrap()
                };
                let (v, f) = (count("vertex"), count("face"));
                assert!(header.contains("binary_little_endian"));
                assert_eq!(bytes.len() - end, v * 24 + f * 13);
                (v, f)
            }
            _ => {
                let n = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
                assert_eq!(bytes.len(), 84 + 50 * n);
                (0, n)
            }
        };
        if ext != "stl" {
            // A closed triangle mesh of a sphere: E = 3F/2, V - E + F = 2.
            assert_eq!(2 * v as i64 - f as i64, 4, "{ext}: V {v}, F {f}");
        }
        triangles.push(f);
    }
    assert!(triangles.windows(2).all(|w| w[0] == w[1]), "{triangles:?}");
}

/// Every listed model meshes (low depth), with a closed mesh.
#[test]
fn mesh_takes_every_listed_model() {
    let list = tracer(&["list"]);
    let text = String::from_utf8_lossy(&list.stdout);
    let names: Vec<&str> = text
        .lines()
        .filter(|l| !l.starts_with(' ') && !l.is_empty())
        .collect();
    assert!(names.len() > 5, "{text}");
    for name in names {
        let path = tmp(&format!("{name}.ply"));
        let out = tracer(&[
            "mesh",
            name,
            "--depth",
            "3",
            "--max-depth",
            "4",
            "--out",
            path.to_str().unwrap(),
            "--stats",
            "json",
            "--no-check",
        ]);
        assert_eq!(out.status.code(), Some(0), "{name}: {out:?}");
        let json = String::from_utf8_lossy(&out.stdout);
        assert!(json.contains("\"watertight\": true"), "{name}: {json}");
        assert!(path.exists());
    }
}
