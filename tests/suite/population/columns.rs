//! The columns of a run's tables (src/population/columns.rs): `results.csv` read back holds the
//! columns and values of `records.parquet`, for every fate, a rigid particle and one that
//! could not be drawn.

use super::common::{FaultySoftPipe, config, plan};
use arrow_array::{Array, Float64Array, Int64Array, StringArray, UInt64Array};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use pseudorigid::material::{NeoHooke, Softness};
use pseudorigid::population::columns::record_columns;
use pseudorigid::population::{Fate, RunOptions, Shard, run};

/// The value in row `i` of `column` as `results.csv` writes it.
fn csv_field(column: &dyn Array, i: usize) -> String {
    if column.is_null(i) {
        return String::new();
    }
    let any = column.as_any();
    if let Some(c) = any.downcast_ref::<UInt64Array>() {
        c.value(i).to_string()
    } else if let Some(c) = any.downcast_ref::<Int64Array>() {
        c.value(i).to_string()
    } else if let Some(c) = any.downcast_ref::<Float64Array>() {
        format!("{:?}", c.value(i))
    } else if let Some(c) = any.downcast_ref::<StringArray>() {
        c.value(i).replace([',', '\n', '\r'], " ")
    } else {
        panic!("a column of type {}", column.data_type())
    }
}

#[test]
fn results_csv_read_back_holds_the_records_parquet_columns_and_values() {
    let soft = FaultySoftPipe::new();
    let case = soft.case(plan());
    let mut out = run(&case, &config(12), Shard::ALL, &RunOptions::default().quiet()).unwrap();
    // A rigid particle (no μ_s), a suspended one (none of these twelve is left at the end time),
    // a patch name and an error with a comma (a space in CSV).
    out.records[0].spec.as_mut().unwrap().softness = Softness::<NeoHooke>::Rigid;
    out.records[2].fate = Fate::Suspended;
    out.patches = vec!["outlet, east".into(), "wall".into()];
    out.records[3].fate = Fate::Failed {
        error: "stopped, on purpose".into(),
    };
    let labels: Vec<&str> = out.records.iter().map(|r| r.fate.label()).collect();
    for fate in ["deposited", "escaped", "suspended", "failed"] {
        assert!(labels.contains(&fate), "no {fate} particle in {labels:?}");
    }
    assert!(out.records.iter().any(|r| r.spec.is_none()));

    let dir = std::env::temp_dir().join(format!("pseudorigid-columns-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("records.parquet");
    pseudorigid::scene::parquet::write_records(&out, &path).unwrap();
    let reader = ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(&path).unwrap())
        .unwrap()
        .build()
        .unwrap();
    let batches: Vec<_> = reader.collect::<Result<_, _>>().unwrap();
    assert_eq!(batches.len(), 1);
    let parquet = &batches[0];
    let text = out.table().unwrap().to_text();
    std::fs::remove_dir_all(&dir).unwrap();

    let columns = record_columns::<NeoHooke>();
    let schema = parquet.schema();
    let parquet_names: Vec<&str> = schema.fields().iter().map(|f| f.name().as_str()).collect();
    let all: Vec<&str> = columns.iter().map(|c| c.name).collect();
    assert_eq!(parquet_names, all);
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let csv: Vec<&str> = columns.iter().filter(|c| c.csv).map(|c| c.name).collect();
    assert_eq!(header, csv);
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), parquet.num_rows());
    for (k, name) in header.iter().enumerate() {
        let column = parquet.column_by_name(name).unwrap();
        for (i, row) in rows.iter().enumerate() {
            assert_eq!(row[k], csv_field(column.as_ref(), i), "column {name}, row {i}");
        }
    }
}
