//! The columns of a run's tables (src/population/columns.rs): `results.csv` read back holds the
//! columns and values of `records.parquet`, for every fate, a rigid particle and one that
//! could not be drawn.

use super::common::{FaultySoftPipe, config, pipe, plan};
use arrow_array::{Array, Float64Array, Int64Array, StringArray, UInt64Array};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use pseudorigid::diagnostics::{Thresholds, Validity};
use pseudorigid::hydro::Brenner;
use pseudorigid::integrator::choice::Auto;
use pseudorigid::integrator::manifold::Manifold;
use pseudorigid::integrator::{ErrorNorm, Stepper, Stokesian, Tolerances};
use pseudorigid::material::{NeoHooke, Softness};
use pseudorigid::population::columns::{ColumnValues, Row, record_columns};
use pseudorigid::population::settling_pipe::SettlingPipe;
use pseudorigid::population::{Case, Fate, ParticleRecord, RunOptions, RunOutput, Shard, run};

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

/// Column `name` of every record of `out`, counts as reals; `None` for an empty value.
fn column_values(out: &RunOutput<NeoHooke>, name: &str) -> Vec<Option<f64>> {
    let column = record_columns::<NeoHooke>()
        .into_iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    out.records
        .iter()
        .map(|r| {
            let row = Row::new(r, &out.patches);
            match column.values {
                ColumnValues::Count(f) => Some(f(&row) as f64),
                ColumnValues::Real(f) => f(&row),
                _ => panic!("{name} is neither a count nor a real"),
            }
        })
        .collect()
}

/// Four particles of `pipe` run by `integ` to [`plan`]'s end.
fn run_pipe<I: Stepper<Softness<NeoHooke>, Brenner> + std::fmt::Debug>(
    integ: &I,
    pipe: &SettlingPipe,
) -> RunOutput<NeoHooke> {
    let case = Case::new(integ, pipe.flow(), pipe.boundary(), pipe, plan());
    run(&case, &config(4), Shard::ALL, &RunOptions::default().quiet()).unwrap()
}

/// The record's steps and the slow manifold's columns, in the order the test reads them.
const MANIFOLD_COLUMNS: [&str; 5] = [
    "steps",
    "manifold_steps",
    "full_steps",
    "manifold_max_ratio",
    "manifold_delta_max",
];

/// The slow-manifold switch in the records and their columns (issue 36, item 3), on the
/// settling pipe: stiff neo-Hookean spheres (Ca = 10⁻³: k = 2/(3Ca) ≈ 667 against the pipe's
/// strain rates ≤ 4Ū/R = 0.2) under `auto` at rtol 10⁻³, which puts them on the slow manifold
/// (δ̄ = 8Ū/(3Rk) = 2·10⁻⁴ ≤ 0.2 δ_max, δ_max = √rtol = 0.0316); rigid spheres under `auto`
/// (the full model: no report) and under `slow_manifold` itself (which passes a rigid particle
/// to the full model). Every accepted step is counted once, on the manifold or of the full
/// model, so `manifold_steps` + `full_steps` = `steps` for every particle; the largest δ on the
/// manifold stays at or below δ_max, the switch's invariant, and the validity flags say so.
#[test]
fn records_carry_the_slow_manifold_switch() {
    let auto = Auto {
        tol: Tolerances::uniform(1e-3).unwrap(),
        norm: ErrorNorm::default(),
    };
    let manifold = Manifold::new(Stokesian::new(1e-3).unwrap()).unwrap();
    let delta_max = 1e-3f64.sqrt();
    let with_auto = |p: &SettlingPipe| run_pipe(&auto, p);
    let with_manifold = |p: &SettlingPipe| run_pipe(&manifold, p);

    let soft = with_auto(&pipe().with_shape(1.0, 1e-3).unwrap());
    for (i, r) in soft.records.iter().enumerate() {
        assert!(!matches!(r.fate, Fate::Failed { .. }), "particle {i}: {:?}", r.fate);
        let m = r
            .integrator
            .manifold
            .unwrap_or_else(|| panic!("particle {i} has no report"));
        assert!(m.manifold_steps > 0 && m.entered >= 1, "particle {i}: {m:?}");
        assert_eq!(m.manifold_steps + m.full_steps, r.stats.steps, "particle {i}: {m:?}");
        assert!(m.max_ratio > 0.0 && m.max_ratio <= delta_max && !m.exceeded(), "{m:?}");
        assert_eq!(m.delta_max, delta_max);
        let validity = Validity::default().with_integrator(r.integrator);
        assert!(validity.flags(&Thresholds::default()).is_empty(), "{validity:?}");
        let json = serde_json::to_string(r).unwrap();
        assert_eq!(serde_json::from_str::<ParticleRecord<NeoHooke>>(&json).unwrap(), *r);
    }
    let [steps, on, off, ratio, bound] = MANIFOLD_COLUMNS.map(|name| column_values(&soft, name));
    for i in 0..steps.len() {
        assert_eq!(Some(on[i].unwrap() + off[i].unwrap()), steps[i], "particle {i}");
        assert!(ratio[i].unwrap() <= bound[i].unwrap(), "particle {i}");
    }
    let total = soft.integrator().manifold.unwrap();
    assert_eq!(total.manifold_steps as f64, on.iter().flatten().sum::<f64>());
    assert!(!total.exceeded(), "{total:?}");

    for (out, reported) in [(with_manifold(&pipe()), true), (with_auto(&pipe()), false)] {
        for (i, r) in out.records.iter().enumerate() {
            assert_eq!(!r.integrator.is_empty(), reported, "particle {i}: {:?}", r.integrator);
            match r.integrator.manifold {
                Some(m) => assert_eq!(
                    (m.manifold_steps, m.entered, m.full_steps),
                    (0, 0, r.stats.steps),
                    "{m:?}"
                ),
                // No report, and none in the JSON: such a record reads as records did before.
                None => assert!(!serde_json::to_string(r).unwrap().contains("manifold")),
            }
        }
        let [steps, on, off, ratio, bound] = MANIFOLD_COLUMNS.map(|name| column_values(&out, name));
        assert!(on.iter().all(|v| *v == Some(0.0)), "{on:?}");
        assert_eq!(off, steps);
        assert!(ratio.iter().all(Option::is_none), "{ratio:?}");
        let expected = reported.then_some(delta_max);
        assert!(bound.iter().all(|v| *v == expected), "{bound:?}");
    }
}
