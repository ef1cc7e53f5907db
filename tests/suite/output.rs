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

/// The blocks of a binary `.vtp`, decoded by hand from VTK's zlib layout (header: block
/// count, uncompressed size, last partial size, compressed sizes; UInt64) at the offset each
/// `<DataArray>` names. `cases/vtk-check.sh` reads the command's files with VTK itself.
fn vtp_block(bytes: &[u8], name: &str) -> (String, Vec<u8>) {
    use std::io::Read;
    let start = bytes.windows(2).position(|w| w == b"\n_").unwrap() + 2;
    let xml = String::from_utf8_lossy(&bytes[..start]).to_string();
    assert!(xml.contains("compressor=\"vtkZLibDataCompressor\""), "{xml}");
    let tag = xml.find(&format!("Name=\"{name}\"")).unwrap();
    let kind = xml[..tag].rsplit("type=\"").next().unwrap();
    let kind = kind[..kind.find('"').unwrap()].to_string();
    let at = tag + xml[tag..].find("offset=\"").unwrap() + 8;
    let offset: usize = xml[at..at + xml[at..].find('"').unwrap()].parse().unwrap();
    let word = |k: usize| u64::from_le_bytes(bytes[start + offset + 8 * k..][..8].try_into().unwrap()) as usize;
    let (blocks, size, compressed) = (word(0), word(1), word(3));
    assert_eq!(blocks, 1);
    let mut raw = Vec::new();
    flate2::read::ZlibDecoder::new(&bytes[start + offset + 32..][..compressed])
        .read_to_end(&mut raw)
        .unwrap();
    assert_eq!(raw.len(), size);
    (kind, raw)
}

/// The binary `.vtp` holds every value bit for bit in double precision.
#[test]
fn binary_vtp_blocks_hold_the_values_bit_for_bit() {
    use pseudorigid::output::vtk::{PointValues, PolyData};
    use pseudorigid::tensor::Vec3;
    let points = vec![
        Vec3::new(5e-324, -0.0, 1.7976931348623157e308),
        Vec3::new(0.1 + 0.2, -1.0 / 3.0, 2.0),
    ];
    let data = PolyData::vertices(points.clone())
        .unwrap()
        .with_array("id", 1, PointValues::Int64(vec![7, -9]))
        .unwrap();
    let bytes = data.to_binary();
    let words = |name: &str| -> Vec<[u8; 8]> {
        let (_, raw) = vtp_block(&bytes, name);
        raw.chunks(8).map(|c| c.try_into().unwrap()).collect()
    };
    assert_eq!(vtp_block(&bytes, "Points").0, "Float64");
    let coords: Vec<u64> = words("Points").into_iter().map(u64::from_le_bytes).collect();
    let expected: Vec<u64> = points.iter().flat_map(|p| p.iter().map(|v| v.to_bits())).collect();
    assert_eq!(coords, expected);
    let ids: Vec<i64> = words("id").into_iter().map(i64::from_le_bytes).collect();
    assert_eq!(ids, [7, -9]);
    let conn: Vec<i64> = words("connectivity").into_iter().map(i64::from_le_bytes).collect();
    assert_eq!(conn, [0, 1]);
    assert!(bytes.ends_with(b"</AppendedData>\n</VTKFile>\n"));
    // The ASCII form of the same data set names the same arrays.
    assert!(
        data.to_xml()
            .contains("Name=\"id\" NumberOfComponents=\"1\" format=\"ascii\"")
    );
}

/// In single precision every float is the f64 rounded to nearest f32 (Rust's `as` and IEEE
/// 754 agree), integers stay Int64, and a value beyond f32's range is refused, not written
/// as infinity.
#[test]
fn single_precision_vtp_rounds_to_nearest_and_refuses_overflow() {
    use pseudorigid::output::vtk::{PointValues, PolyData};
    use pseudorigid::tensor::Vec3;
    let points = vec![Vec3::new(0.1, -1.0 / 3.0, 1e-40), Vec3::new(3.4e38, 2.0, -0.0)];
    let r = vec![std::f64::consts::PI, 1.0 + f64::EPSILON];
    let data = PolyData::vertices(points.clone())
        .unwrap()
        .with_array("r1", 1, PointValues::Float64(r.clone()))
        .unwrap()
        .single_precision()
        .unwrap();
    let bytes = data.to_binary();
    let floats = |name: &str| -> Vec<u32> {
        let (kind, raw) = vtp_block(&bytes, name);
        assert_eq!(kind, "Float32");
        raw.chunks(4)
            .map(|c| u32::from_le_bytes(c.try_into().unwrap()))
            .collect()
    };
    let nearest = |v: &[f64]| -> Vec<u32> { v.iter().map(|&x| (x as f32).to_bits()).collect() };
    let coords: Vec<f64> = points.iter().flat_map(|p| p.iter().copied()).collect();
    assert_eq!(floats("Points"), nearest(&coords));
    assert_eq!(floats("r1"), nearest(&r));
    // 0.1 rounds to the f32 nearest to it: within half an f32 ulp (2⁻²⁴ relative).
    assert!((f32::from_bits(floats("Points")[0]) as f64 - 0.1).abs() <= 0.1 * 2f64.powi(-24));
    assert_eq!(vtp_block(&bytes, "connectivity").0, "Int64");
    // 4e38 > f32::MAX ≈ 3.4028e38.
    let too_big = PolyData::vertices(vec![Vec3::new(4e38, 0.0, 0.0)])
        .unwrap()
        .single_precision();
    assert!(too_big.is_err());
    let later = PolyData::vertices(vec![Vec3::zeros()])
        .unwrap()
        .single_precision()
        .unwrap()
        .with_array("r1", 1, PointValues::Float64(vec![-1e39]));
    assert!(later.is_err());
}
