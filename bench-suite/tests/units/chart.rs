//! Tests of [`bench_suite::chart`].

use bench_suite::chart::*;

#[test]
fn writes_a_png_with_bars() {
    let dir = std::env::temp_dir().join(format!("bench-suite-chart-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("c.png");
    let groups = vec![
        Group {
            label: "a".into(),
            bars: vec![
                Some(Bar {
                    seconds: 0.5,
                    stopped: false,
                }),
                None,
            ],
        },
        Group {
            label: "b".into(),
            bars: vec![
                Some(Bar {
                    seconds: 20.0,
                    stopped: false,
                }),
                Some(Bar {
                    seconds: 3.0,
                    stopped: true,
                }),
            ],
        },
    ];
    bar_chart(&path, "t", &["x", "y"], &groups).unwrap();
    let img = image::open(&path).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (1200, 600));
    // the first series' colour appears (the filled bars were drawn)
    let red = image::Rgb([0xd6, 0x27, 0x28]);
    assert!(img.pixels().filter(|p| **p == red).count() > 100);
    std::fs::remove_dir_all(&dir).ok();
}
