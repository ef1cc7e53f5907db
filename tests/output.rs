//! Output helpers (src/output): atomic writes, CSV tables, SVG figures.

use pseudorigid::output::{Csv, Figure, OutputError, Panel, Series, write_atomic};

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("pseudorigid-output-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

#[test]
fn atomic_write_replaces_and_leaves_no_temporary() {
    let dir = scratch("atomic");
    let path = dir.join("nested").join("a.csv");
    write_atomic(&path, b"old").unwrap();
    write_atomic(&path, b"new").unwrap();
    assert_eq!(std::fs::read(&path).unwrap(), b"new");
    let names: Vec<_> = std::fs::read_dir(path.parent().unwrap())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names, vec![std::ffi::OsString::from("a.csv")]);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn csv_checks_columns_and_round_trips_numbers() {
    let mut csv = Csv::new(&["a", "b"]);
    assert!(matches!(
        csv.push_numbers(&[1.0]),
        Err(OutputError::Columns { expected: 2, got: 1 })
    ));
    csv.push_numbers(&[0.1 + 0.2, -1e-300]).unwrap();
    assert_eq!(csv.len(), 1);
    let text = csv.to_text();
    assert_eq!(text, "a,b\n0.30000000000000004,-1e-300\n");
    let back: f64 = text.lines().nth(1).unwrap().split(',').next().unwrap().parse().unwrap();
    assert_eq!(back, 0.1 + 0.2);
}

#[test]
fn figure_renders_every_series() {
    let panel = Panel::new("t", "x", "y")
        .with(Series::line("line", vec![(0.0, 0.0), (1.0, 1.0), (2.0, 0.5)], 1))
        .with(Series::points("", vec![(0.5, 0.5), (1.5, 0.25)], 2));
    let svg = Figure::grid(vec![panel.clone(), panel], 2, (200, 150))
        .to_svg()
        .unwrap();
    assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    assert_eq!(svg.matches("<circle").count(), 4);
    assert!(svg.contains("<polyline"));
}
