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

/// The binary `.vtp` holds every value bit for bit: each appended block is a UInt64 byte count
/// and the raw little-endian values, at the offset its `<DataArray>` names (decoded here by
/// hand; `cases/vtk-check.sh` reads the command's files with VTK itself).
#[test]
fn binary_vtp_blocks_hold_the_values_bit_for_bit() {
    use pseudorigid::output::vtk::{PolyData, Values};
    use pseudorigid::tensor::Vec3;
    let points = vec![
        Vec3::new(5e-324, -0.0, 1.7976931348623157e308),
        Vec3::new(0.1 + 0.2, -1.0 / 3.0, 2.0),
    ];
    let data = PolyData::vertices(points.clone())
        .unwrap()
        .with_array("id", 1, Values::Int64(vec![7, -9]))
        .unwrap();
    let bytes = data.to_binary();
    let start = bytes.windows(2).position(|w| w == b"\n_").unwrap() + 2;
    let xml = String::from_utf8_lossy(&bytes[..start]).to_string();
    assert!(!xml.contains("format=\"ascii\""), "{xml}");
    let block = |name: &str| -> Vec<[u8; 8]> {
        let tag = xml.find(&format!("Name=\"{name}\"")).unwrap();
        let at = tag + xml[tag..].find("offset=\"").unwrap() + 8;
        let offset: usize = xml[at..at + xml[at..].find('"').unwrap()].parse().unwrap();
        let raw = &bytes[start + offset..];
        let len = u64::from_le_bytes(raw[..8].try_into().unwrap()) as usize;
        raw[8..8 + len].chunks(8).map(|c| c.try_into().unwrap()).collect()
    };
    let coords: Vec<u64> = block("Points").into_iter().map(u64::from_le_bytes).collect();
    let expected: Vec<u64> = points.iter().flat_map(|p| p.iter().map(|v| v.to_bits())).collect();
    assert_eq!(coords, expected);
    let ids: Vec<i64> = block("id").into_iter().map(i64::from_le_bytes).collect();
    assert_eq!(ids, [7, -9]);
    let conn: Vec<i64> = block("connectivity").into_iter().map(i64::from_le_bytes).collect();
    assert_eq!(conn, [0, 1]);
    assert!(bytes.ends_with(b"</AppendedData>\n</VTKFile>\n"));
    // The ASCII form of the same data set names the same arrays.
    assert!(
        data.to_xml()
            .contains("Name=\"id\" NumberOfComponents=\"1\" format=\"ascii\"")
    );
}
