//! The examples' CSV and figure helpers (`examples/common/`): files appear, numbers round-trip,
//! awkward data (empty, NaN, constant, non-positive on log axes) draws without panicking.

use crate::common;

use std::path::PathBuf;

use common::csv::{fmt_f64, quote, write_csv, CsvWriter};
use common::plot::{self, Category, CategoryGrid, Figure, Grid, Series};

fn out_dir(name: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let target = exe.parent().and_then(|d| d.parent()).unwrap().to_path_buf();
    let dir = target.join("analysis_plot_test").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

#[test]
fn numbers_round_trip_through_csv_text() {
    for v in [
        0.0,
        -0.0,
        1.0,
        0.1,
        1.0 / 3.0,
        1e-7,
        -2.5e-300,
        6.02e23,
        123456.789,
        f64::MAX,
        f64::MIN_POSITIVE,
    ] {
        let s = fmt_f64(v);
        assert_eq!(
            s.parse::<f64>().unwrap().to_bits(),
            v.to_bits(),
            "{v} -> {s}"
        );
    }
    assert_eq!(fmt_f64(f64::NAN), "NaN");
    assert_eq!(fmt_f64(0.25), "0.25");
    assert_eq!(fmt_f64(1.5e-7), "1.5e-7");
    assert_eq!(quote("a,b"), "\"a,b\"");
    assert_eq!(quote("say \"hi\""), "\"say \"\"hi\"\"\"");
    assert_eq!(quote("plain"), "plain");
}

#[test]
fn csv_files_are_written_with_their_folder() {
    let dir = out_dir("csv");
    let path = dir.join("deeper").join("t.csv");
    write_csv(&path, &["eta", "x"], [[2.0, 0.5], [2.5, -1e-9]]).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text, "eta,x\n2,0.5\n2.5,-1e-9\n");
    let mut w = CsvWriter::create(dir.join("r.csv"), &["series", "x"]).unwrap();
    w.record(&["a, b", "1"]).unwrap();
    assert!(
        w.row(&[1.0, 2.0, 3.0]).is_err(),
        "wrong field count must be an error"
    );
    w.finish().unwrap();
    let text = std::fs::read_to_string(dir.join("r.csv")).unwrap();
    assert_eq!(text, "series,x\n\"a, b\",1\n");
}

#[test]
fn every_plot_kind_writes_png_svg_and_csv() {
    let dir = out_dir("kinds");
    let pts: Vec<(f64, f64)> = (0..2000)
        .map(|i| {
            let r = 2.0 + i as f64 / 1000.0;
            (r, (r * 7.0).sin())
        })
        .collect();
    let fig = Figure::new("η sweep: ν₁ = 0.125, K = 30", "η", "x_r").with_mark(2.5, "2.5");
    for ext in ["png", "svg"] {
        let f = dir.join(format!("bif.{ext}"));
        plot::bifurcation(&f, &fig, &pts).unwrap();
        assert!(std::fs::metadata(&f).unwrap().len() > 1000);
        assert!(dir.join("bif.csv").exists());
        let series = [
            Series::new("a", pts.clone()),
            Series::new("", vec![(2.0, 0.0)]),
        ];
        plot::scatter(dir.join(format!("sc.{ext}")), &fig, &series).unwrap();
        plot::lines(
            dir.join(format!("ln.{ext}")),
            &fig.clone().with_max_jump(0.05),
            &series,
        )
        .unwrap();
        let grid = Grid {
            xs: vec![0.0, 1.0, 2.0],
            ys: vec![0.0, 1.0],
            values: vec![0.0, 1.0, 2.0, 3.0, f64::NAN, 5.0],
            z_range: None,
        };
        plot::heatmap(dir.join(format!("hm.{ext}")), &fig, &grid, "value").unwrap();
        let cats = CategoryGrid {
            xs: vec![0.0, 1.0, 2.0],
            ys: vec![0.0, 1.0],
            cells: vec![Some(0), Some(1), None, Some(1), Some(7), Some(0)],
        };
        let legend = [
            Category {
                label: "A0: period 1, with a comma".into(),
                colour: plot::series_colour(0),
            },
            Category {
                label: "A1: period 3".into(),
                colour: plot::series_colour(1),
            },
        ];
        plot::category_map(dir.join(format!("cm.{ext}")), &fig, &cats, &legend).unwrap();
        assert!(plot::category_map(
            dir.join(format!("bad.{ext}")),
            &fig,
            &CategoryGrid {
                cells: vec![None],
                ..cats.clone()
            },
            &legend
        )
        .is_err());
    }
    // The index of an unknown category (7) is kept, drawn as none, with an empty label.
    let csv = std::fs::read_to_string(dir.join("cm.csv")).unwrap();
    assert!(
        csv.starts_with(
            "x,y,category,label\n0,0,0,\"A0: period 1, with a comma\"\n1,0,1,A1: period 3\n2,0,,\n"
        ),
        "{csv}"
    );
    assert!(csv.contains("1,1,7,\n"), "{csv}");
    let csv = std::fs::read_to_string(dir.join("hm.csv")).unwrap();
    assert!(csv.starts_with("x,y,value\n0,0,0\n1,0,1\n"), "{csv}");
    assert!(csv.contains("1,1,NaN"), "{csv}");
}

#[test]
fn awkward_data_does_not_panic() {
    let dir = out_dir("awkward");
    let fig = Figure::new("awkward", "x", "y");
    let log = fig.clone().with_log(true, true).with_markers();
    let cases: Vec<Vec<(f64, f64)>> = vec![
        vec![],
        vec![(1.0, 1.0)],
        vec![(1.0, 2.0); 5],
        vec![(f64::NAN, 1.0), (2.0, f64::INFINITY), (3.0, 3.0)],
        vec![(0.0, -1.0), (1.0, 0.0), (10.0, 1e-12), (1e6, 1e3)],
        vec![(-1e300, 1e300), (1e300, -1e300)],
    ];
    for (i, pts) in cases.iter().enumerate() {
        let s = [Series::new("s", pts.clone())];
        plot::bifurcation(dir.join(format!("b{i}.png")), &fig, pts).unwrap();
        plot::scatter(dir.join(format!("s{i}.png")), &fig, &s).unwrap();
        plot::lines(dir.join(format!("l{i}.png")), &fig, &s).unwrap();
        plot::lines(dir.join(format!("g{i}.png")), &log, &s).unwrap();
    }
    let constant = Grid {
        xs: vec![1.0],
        ys: vec![1.0],
        values: vec![4.0],
        z_range: None,
    };
    plot::heatmap(dir.join("h1.png"), &fig, &constant, "z").unwrap();
    let all_nan = Grid {
        values: vec![f64::NAN],
        ..constant.clone()
    };
    plot::heatmap(dir.join("h2.png"), &fig, &all_nan, "z").unwrap();
    let bad = Grid {
        values: vec![1.0, 2.0],
        ..constant
    };
    let e = plot::heatmap(dir.join("h3.png"), &fig, &bad, "z").unwrap_err();
    assert!(e.to_string().contains("1 × 1 cells but 2 values"), "{e}");
    let e = plot::scatter(dir.join("x.jpg"), &fig, &[]).unwrap_err();
    assert!(e.to_string().contains(".png or .svg"), "{e}");
}
