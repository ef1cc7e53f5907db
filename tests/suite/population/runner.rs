//! The population runner: closed-form deposition, identical results for every layout (serial,
//! 1–3 threads, shards, checkpoints and resumes), exact file round trips, typed errors.

use super::common as population_common;

use population_common::{FaultySoftPipe, config, pipe, plan};
use pseudorigid::integrator::Stokesian;
use pseudorigid::material::NeoHooke;
use pseudorigid::population::settling_pipe::sphere_deposition;
use pseudorigid::population::{
    Case, Fate, Fingerprint, PopulationError, RunConfig, RunOptions, RunOutput, Shard, checkpoint_dir, particle_rng,
    run, run_in_dir, seal,
};
use std::time::Duration;

fn thread_pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap()
}

/// A fresh empty folder under the target directory.
fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("population-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Rigid spheres with an overdamped barycentre deposit where the closed form says
/// ([`sphere_deposition`]), and escape exactly when the closed form's landing point lies beyond
/// the outlet.
#[test]
fn rigid_spheres_deposit_at_the_closed_form_point() {
    let case_pipe = pipe();
    let tol = 1e-9;
    let stokes = Stokesian::overdamped(tol).unwrap();
    let plan = pseudorigid::driver::Plan::new(1e4, 0.1).unwrap();
    let case = Case::new(&stokes, case_pipe.flow(), case_pipe.boundary(), &case_pipe, plan);
    let config = Fingerprint::new("settling pipe").particles(&case_pipe).config(7, 48);
    let out = run(&case, &config, Shard::ALL, &RunOptions::default().quiet()).unwrap();
    let counts = out.counts();
    assert_eq!(counts.total(), 48);
    assert!(counts.deposited >= 5 && counts.escaped >= 5, "{counts:?}");
    assert_eq!(counts.suspended + counts.failed, 0, "{counts:?}");
    assert_eq!(out.patches, ["outlet", "wall"]);
    for r in &out.records {
        let x0 = r.spec.as_ref().unwrap().position;
        let [x1, y, z, t] = sphere_deposition(20.0, 1.0, 0.1, 0.5, x0[1], x0[2]).unwrap();
        match &r.fate {
            Fate::Deposited { patch, position, time } => {
                assert_eq!(*patch, 1);
                // The controller keeps each step's local error below tol·(1 + |y|) per
                // component (|y| ≤ L = 200), and local errors add at most linearly over the
                // accepted steps; the contact itself is located to |g| ≤ 1e-9 d_eq, which moves
                // the landing point by less than that times the slope u₁/v_s ≤ 20 near the wall.
                let bound = (r.stats.steps as f64 + 1.0) * tol * 201.0 + 20.0 * 1e-9;
                let err = (position - nalgebra::Vector3::new(x1, y, z)).amax();
                assert!(err <= bound, "particle {}: error {err:e} > {bound:e}", r.index);
                // t = (y₀ − y)/v_s: the same bound divided by v_s.
                assert!((time - t).abs() <= bound / 0.1, "particle {}: t {time} vs {t}", r.index);
                assert!(x1 < 200.0);
            }
            Fate::Escaped { patch, .. } => {
                assert_eq!(*patch, 0);
                assert!(x1 > 200.0, "particle {} escaped but lands at x1 = {x1}", r.index);
            }
            other => panic!("particle {}: {other:?}", r.index),
        }
    }
    // The table: one row per particle; a deposited rigid sphere is still a sphere of radius
    // 1/2 (F stays a rotation, projected onto SO(3) every step: round-off only).
    let text = out.table().unwrap().to_text();
    let rows: Vec<Vec<&str>> = text.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 48);
    for (row, r) in rows.iter().zip(&out.records) {
        assert_eq!(row[0], r.index.to_string());
        assert_eq!(row[1], r.fate.label());
        assert_eq!(row[3], if row[1] == "deposited" { "wall" } else { "outlet" });
        for c in &row[8..11] {
            assert!((c.parse::<f64>().unwrap() - 0.5).abs() <= 1e-12, "{row:?}");
        }
        assert_eq!(row[17], "", "rigid: no shear modulus");
    }
}

/// Serial, and 1, 2 and 3 threads give the same bytes; the population holds every fate.
#[test]
fn same_results_serial_and_on_any_number_of_threads() {
    let soft = FaultySoftPipe::new();
    let case = soft.case(plan());
    let config = config(40);
    let serial = run(&case, &config, Shard::ALL, &RunOptions::default().serial().quiet()).unwrap();
    let counts = serial.counts();
    assert!(
        counts.deposited > 0 && counts.escaped > 0 && counts.suspended > 0 && counts.failed > 0,
        "{counts:?}"
    );
    let bytes = serial.to_json().unwrap();
    for threads in [1, 2, 3] {
        let out = thread_pool(threads).install(|| run(&case, &config, Shard::ALL, &RunOptions::default().quiet()));
        assert!(
            out.unwrap().to_json().unwrap() == bytes,
            "{threads} threads differ from serial"
        );
    }
    // Particles that run out of their step budget fail with a text that does not depend on
    // the wall time they took.
    let tight = pseudorigid::driver::Plan::new(150.0, 0.1)
        .unwrap()
        .with_budget(pseudorigid::driver::Budget {
            max_steps: 30,
            wall_time: None,
        });
    let case = soft.case(tight);
    let serial = run(&case, &config, Shard::ALL, &RunOptions::default().serial().quiet()).unwrap();
    let budget_failures = serial
        .records
        .iter()
        .filter(|r| matches!(&r.fate, Fate::Failed { error } if error.starts_with("step budget exceeded after 30 steps at t = ")))
        .count();
    assert!(budget_failures > 0, "{:?}", serial.counts());
    let parallel = thread_pool(2).install(|| run(&case, &config, Shard::ALL, &RunOptions::default().quiet()));
    assert!(parallel.unwrap().to_json().unwrap() == serial.to_json().unwrap());
}

/// Shards 0/3, 1/3, 2/3 (from text and from Slurm variables) merge to the unsharded run, byte
/// for byte; merges of the wrong parts are typed errors.
#[test]
fn merged_shards_equal_the_whole_run() {
    let soft = FaultySoftPipe::new();
    let case = soft.case(plan());
    let config = config(31);
    let opts = RunOptions::default().quiet();
    let whole = run(&case, &config, Shard::ALL, &opts).unwrap();
    let dir = scratch("shards");
    let mut paths = Vec::new();
    for k in 0..3u64 {
        let vars = |name: &str| match name {
            "SLURM_ARRAY_TASK_ID" => Some((k + 4).to_string()),
            "SLURM_ARRAY_TASK_MIN" => Some("4".to_string()),
            "SLURM_ARRAY_TASK_COUNT" => Some("3".to_string()),
            _ => None,
        };
        let shard = Shard::from_vars(vars).unwrap().unwrap();
        assert_eq!(shard, format!("{k}/3").parse().unwrap());
        let out = run_in_dir(&case, &config, shard, &dir, &opts).unwrap();
        assert_eq!(out.records.len() as u64, shard.len(31));
        // The checkpoint is the shard's only file of records, and it reads back as the output.
        assert_eq!(RunOutput::<NeoHooke>::read_checkpoint(&dir, shard).unwrap(), out);
        paths.push(checkpoint_dir(&dir, shard));
    }
    let mut written: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    written.sort();
    assert_eq!(
        written,
        [
            "checkpoint-0000-of-0003",
            "checkpoint-0001-of-0003",
            "checkpoint-0002-of-0003"
        ]
    );
    // Merge order does not matter.
    paths.reverse();
    let parts = || {
        paths
            .iter()
            .map(RunOutput::<NeoHooke>::read_checkpoint_dir)
            .collect::<Result<Vec<_>, _>>()
            .unwrap()
    };
    let merged = RunOutput::<NeoHooke>::merge(parts()).unwrap();
    assert!(merged.to_json().unwrap() == whole.to_json().unwrap());
    assert_eq!(merged.table().unwrap().to_text(), whole.table().unwrap().to_text());
    assert_eq!(RunOutput::<NeoHooke>::merge_dir(&dir).unwrap(), merged);

    let mut missing = parts();
    missing.pop();
    assert!(matches!(
        RunOutput::merge(missing),
        Err(PopulationError::MissingShards { count: 3, ref missing }) if missing.len() == 1
    ));
    let mut repeated = parts();
    repeated[0] = repeated[1].clone();
    assert!(matches!(
        RunOutput::merge(repeated),
        Err(PopulationError::RepeatedShard { .. })
    ));
    let mut foreign = parts();
    foreign[2].config_hash = "0000000000000000".to_string();
    assert!(matches!(
        RunOutput::merge(foreign),
        Err(PopulationError::ConfigMismatch { .. })
    ));
    let mut short = parts();
    let _ = short[1].records.pop();
    assert!(matches!(
        RunOutput::merge(short),
        Err(PopulationError::IncompleteShard { .. })
    ));
    let mut unsharded_too = parts();
    unsharded_too.push(whole);
    assert!(matches!(
        RunOutput::merge(unsharded_too),
        Err(PopulationError::ShardMismatch { .. })
    ));
}

/// In-process checkpoints: a finished checkpoint resumes to the same bytes without work, a
/// new run refuses an existing checkpoint, and a different run refuses it with its hash.
#[test]
fn checkpoint_guards_and_resume_of_a_finished_run() {
    let soft = FaultySoftPipe::new();
    let case = soft.case(plan());
    let config = config(12);
    let dir = scratch("checkpoint");
    let opts = RunOptions::default().quiet().with_checkpoints(&dir, Duration::ZERO);
    let first = run(&case, &config, Shard::ALL, &opts).unwrap();
    let again = run(&case, &config, Shard::ALL, &opts.clone().resume(true)).unwrap();
    assert!(first.to_json().unwrap() == again.to_json().unwrap());
    // Every record was flushed (interval 0: a chunk per received batch), and resuming a
    // finished run added no chunk.
    let chunks = std::fs::read_dir(&dir).unwrap().count();
    assert!((1..=12).contains(&chunks), "{chunks} chunks");
    assert!(matches!(
        run(&case, &config, Shard::ALL, &opts),
        Err(PopulationError::CheckpointExists { chunks: c, .. }) if c == chunks
    ));
    let other = RunConfig {
        seed: config.seed + 1,
        ..config.clone()
    };
    let err = run(&case, &other, Shard::ALL, &opts.clone().resume(true)).unwrap_err();
    assert!(
        matches!(&err, PopulationError::ConfigMismatch { expected, found, .. }
            if *expected == case.config_hash(&other) && *found == case.config_hash(&config)),
        "{err}"
    );
    let err = run(&case, &config, Shard::new(1, 2).unwrap(), &opts.clone().resume(true)).unwrap_err();
    assert!(matches!(err, PopulationError::ShardMismatch { .. }), "{err}");

    // A chunk that is not ours: cut short (not something write_atomic leaves, but a copy
    // gone wrong), or holding a particle of another shard.
    let chunk = std::fs::read_dir(&dir).unwrap().next().unwrap().unwrap().path();
    let text = chunk_text(&chunk);
    std::fs::write(dir.join("chunk-90000000.json"), &text[..text.len() / 2]).unwrap();
    let err = run(&case, &config, Shard::ALL, &opts.clone().resume(true)).unwrap_err();
    assert!(
        matches!(&err, PopulationError::Json { path: Some(p), .. } if p.ends_with("chunk-90000000.json")),
        "{err}"
    );
    let mut value: serde_json::Value = serde_json::from_str(&text).unwrap();
    value["records"][0]["index"] = serde_json::json!(12);
    std::fs::write(dir.join("chunk-90000000.json"), value.to_string()).unwrap();
    let err = run(&case, &config, Shard::ALL, &opts.clone().resume(true)).unwrap_err();
    assert!(matches!(err, PopulationError::ForeignRecord { index: 12, .. }), "{err}");
    value["records"][0]["index"] = serde_json::json!(3);
    value["records"][0]["stats"]["steps"] = serde_json::json!(123_456_789);
    std::fs::write(dir.join("chunk-90000000.json"), value.to_string()).unwrap();
    let err = run(&case, &config, Shard::ALL, &opts.clone().resume(true)).unwrap_err();
    assert!(
        matches!(err, PopulationError::ConflictingRecords { index: 3, .. }),
        "{err}"
    );
}

/// The JSON text of a checkpoint chunk (written gzipped). The tests write edited chunks back
/// as plain text, which the reader takes too (it goes by gzip's magic number, not the name).
fn chunk_text(path: &std::path::Path) -> String {
    use std::io::Read as _;
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..2], [0x1f, 0x8b], "{} is not gzipped", path.display());
    let mut text = String::new();
    flate2::read::GzDecoder::new(bytes.as_slice())
        .read_to_string(&mut text)
        .unwrap();
    text
}

/// Change the first digit of the first `"key":<integer>` in `text` (a different value, the JSON
/// still valid).
fn edit_digit(text: &str, key: &str) -> String {
    let at = text.find(&format!("\"{key}\":")).unwrap() + key.len() + 3;
    let digit = text.as_bytes()[at];
    assert!(digit.is_ascii_digit(), "{key} is not followed by a number");
    let new = if digit == b'9' { '1' } else { (digit + 1) as char };
    format!("{}{new}{}", &text[..at], &text[at + 1..])
}

/// A checkpoint chunk or a shard file edited after it was written (one digit, valid JSON, no
/// structural guard fires) is refused by its checksum, naming the file; another code
/// version's or an unsealed file is refused as such; the untouched files resume and merge.
#[test]
fn edited_chunk_and_shard_are_refused_by_their_checksum() {
    let soft = FaultySoftPipe::new();
    let case = soft.case(plan());
    let config = config(6);
    let dir = scratch("checksum");
    let opts = RunOptions::default()
        .quiet()
        .with_checkpoints(dir.join("cp"), Duration::ZERO);
    let first = run(&case, &config, Shard::ALL, &opts).unwrap();
    let chunk = std::fs::read_dir(dir.join("cp"))
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let text = chunk_text(&chunk);
    let resume = || run(&case, &config, Shard::ALL, &opts.clone().resume(true));
    for edited in [
        edit_digit(&text, "steps"),
        edit_digit(&text, "rhs_evals"),
        // The stored checksum itself.
        {
            let at = text.find("\"checksum\":\"").unwrap() + 12;
            let c = if &text[at..=at] == "0" { "1" } else { "0" };
            format!("{}{c}{}", &text[..at], &text[at + 1..])
        },
    ] {
        assert_ne!(edited, text);
        std::fs::write(&chunk, &edited).unwrap();
        let err = resume().unwrap_err();
        assert!(
            matches!(&err, PopulationError::Checksum { path, .. } if *path == chunk),
            "{err}"
        );
        assert!(err.to_string().contains(&chunk.display().to_string()), "{err}");
    }
    std::fs::write(&chunk, text.replace(seal::VERSION, "0.0.0-other")).unwrap();
    assert!(matches!(resume().unwrap_err(), PopulationError::Version { path, .. } if path == chunk));
    let unsealed = &text[..text.find(",\"version\"").unwrap()];
    std::fs::write(&chunk, format!("{unsealed}}}")).unwrap();
    assert!(matches!(resume().unwrap_err(), PopulationError::Unsealed { path } if path == chunk));
    std::fs::write(&chunk, &text).unwrap();
    assert!(resume().unwrap().to_json().unwrap() == first.to_json().unwrap());

    // Shards are merged from their checkpoints: an edited chunk of shard 1 stops the merge.
    let opts = RunOptions::default().quiet();
    let shards = dir.join("shards");
    for k in 0..2u64 {
        let _ = run_in_dir(&case, &config, Shard::new(k, 2).unwrap(), &shards, &opts).unwrap();
    }
    let folder = checkpoint_dir(&shards, Shard::new(1, 2).unwrap());
    let shard_chunk = std::fs::read_dir(&folder).unwrap().next().unwrap().unwrap().path();
    let text = chunk_text(&shard_chunk);
    std::fs::write(&shard_chunk, edit_digit(&text, "steps")).unwrap();
    let err = RunOutput::<NeoHooke>::merge_dir(&shards).unwrap_err();
    assert!(
        matches!(&err, PopulationError::Checksum { path, .. } if *path == shard_chunk),
        "{err}"
    );
    // The run's size is sealed too: a shard cannot pass as complete by claiming fewer particles.
    std::fs::write(&shard_chunk, edit_digit(&text, "particles")).unwrap();
    assert!(RunOutput::<NeoHooke>::merge_dir(&shards).is_err());
    std::fs::write(&shard_chunk, &text).unwrap();
    let merged = RunOutput::<NeoHooke>::merge_dir(&shards).unwrap();
    assert!(merged.to_json().unwrap() == first.to_json().unwrap());
}

/// Records are written and read back bit for bit, including subnormal, huge and negative-zero
/// components, and particle k draws the same numbers whatever else has been drawn.
#[test]
fn records_round_trip_exactly() {
    let soft = FaultySoftPipe::new();
    let case = soft.case(plan());
    let mut out = run(&case, &config(6), Shard::ALL, &RunOptions::default().quiet()).unwrap();
    let end = out.records[0].end.as_mut().unwrap();
    end.x = nalgebra::Vector3::new(5e-324, -0.0, 1.7976931348623157e308);
    end.t = 0.1 + 0.2;
    let path = scratch("roundtrip").join("out.json");
    out.write_json(&path).unwrap();
    let back = RunOutput::<NeoHooke>::read_json(&path).unwrap();
    let bits = |o: &RunOutput<NeoHooke>| {
        o.records
            .iter()
            .flat_map(|r| {
                r.end
                    .iter()
                    .flat_map(|s| s.x.iter().chain(s.f.iter()).chain([&s.t]).map(|v| v.to_bits()))
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&back), bits(&out));
    assert_eq!(back, out);

    use rand::RngExt;
    let mut a = particle_rng(3, 17);
    let mut b = particle_rng(3, 17);
    let _: f64 = particle_rng(3, 16).random();
    assert_eq!(a.random::<u64>(), b.random::<u64>());
    assert_ne!(particle_rng(3, 17).random::<u64>(), particle_rng(3, 18).random::<u64>());
    assert_ne!(particle_rng(3, 17).random::<u64>(), particle_rng(4, 17).random::<u64>());
}

/// A cached run reports the wall time of its computation, not of the read: the clock file
/// beside the cache keeps it (the run's own file is the same bytes whatever the clock), and a
/// run cached without one says the time is not known.
#[test]
fn a_cached_run_reports_its_computation_time() {
    let soft = FaultySoftPipe::new();
    let case = soft.case(plan());
    let file = scratch("clock").join("run.json");
    // The computation takes at least the pause, the read back far less than it.
    let pause = Duration::from_millis(300);
    let computed = RunOutput::read_or_run(Some(&file), || {
        std::thread::sleep(pause);
        run(&case, &config(3), Shard::ALL, &RunOptions::default().quiet())
    })
    .unwrap();
    let seconds = computed.seconds.unwrap();
    assert!(seconds >= pause.as_secs_f64(), "{seconds} s");
    let read = RunOutput::<NeoHooke>::read_or_run(Some(&file), || -> Result<_, PopulationError> {
        panic!("a cached run is read, not rerun")
    })
    .unwrap();
    assert_eq!(read.output, computed.output);
    assert_eq!(read.seconds.map(f64::to_bits), Some(seconds.to_bits()));
    let bytes = std::fs::read(&file).unwrap();
    assert_eq!(bytes, computed.output.to_json().unwrap());
    assert_eq!(read.seconds_cell(), format!("{seconds:.1}"));

    for clock in [None, Some("not a number"), Some("-1"), Some("NaN")] {
        let clock_file = pseudorigid::population::Computed::<NeoHooke>::clock_file(&file);
        match clock {
            None => std::fs::remove_file(&clock_file).unwrap_or(()),
            Some(text) => std::fs::write(&clock_file, text).unwrap(),
        }
        let unknown = RunOutput::<NeoHooke>::read_or_run(Some(&file), || -> Result<_, PopulationError> {
            panic!("a cached run is read, not rerun")
        })
        .unwrap();
        assert_eq!(unknown.seconds, None, "clock file {clock:?}");
        assert_eq!(
            (unknown.seconds_cell().as_str(), unknown.time_label().as_str()),
            ("", "time not kept")
        );
    }
}

/// Shards from text and the environment, and their errors.
#[test]
fn shard_specifications() {
    let s: Shard = "3/16".parse().unwrap();
    assert_eq!((s.index(), s.count(), s.to_string()), (3, 16, "3/16".to_string()));
    assert_eq!(s.indices(40).collect::<Vec<_>>(), [3, 19, 35]);
    assert_eq!(s.len(40), 3);
    assert_eq!(Shard::new(2, 3).unwrap().len(2), 0);
    for bad in ["3", "a/2", "1/", "-1/2"] {
        assert!(
            matches!(bad.parse::<Shard>(), Err(PopulationError::BadShard { .. })),
            "{bad}"
        );
    }
    for (k, n) in [(2, 2), (0, 0)] {
        assert!(matches!(Shard::new(k, n), Err(PopulationError::ShardOutOfRange { .. })));
    }
    assert_eq!(Shard::from_vars(|_| None).unwrap(), None);
    let env = |id: &'static str| {
        move |name: &str| match name {
            "SLURM_ARRAY_TASK_ID" => Some(id.to_string()),
            "SLURM_ARRAY_TASK_COUNT" => Some("4".to_string()),
            _ => None,
        }
    };
    assert_eq!(Shard::from_vars(env("3")).unwrap(), Some(Shard::new(3, 4).unwrap()));
    assert!(matches!(
        Shard::from_vars(env("4")),
        Err(PopulationError::ShardOutOfRange { index: 4, count: 4 })
    ));
    assert!(matches!(
        Shard::from_vars(env("x")),
        Err(PopulationError::BadEnvironment { .. })
    ));
}

/// The log line of a run off a terminal: count, percentage, the rate of this process's
/// particles (not those resumed from a checkpoint) and the ETA from that rate.
#[test]
fn progress_log_lines() {
    use pseudorigid::population::progress::progress_line;
    // 250 of 1000 done, 200 of them in 100 s here: 2 particles/s, 750 left: 375 s = 6m15s.
    assert_eq!(
        progress_line("run", 250, 1000, 200, Duration::from_secs(100)),
        "run: 250/1000 particles (25.0 %), 2.0 particles/s, ETA 6m15s"
    );
    assert_eq!(
        progress_line("run", 10, 100_000, 10, Duration::from_secs(1)),
        "run: 10/100000 particles (0.0 %), 10.0 particles/s, ETA 2h46m39s"
    );
    assert!(progress_line("run", 0, 10, 0, Duration::ZERO).ends_with("ETA unknown"));
    assert!(progress_line("run", 0, 0, 0, Duration::ZERO).contains("(100.0 %)"));
}

/// A disc weighted by Poiseuille flux: s = ρ²/R² has density 2(1 − s) (the flux ∝ 1 − s
/// through the annulus ds, which holds area ∝ ds), so E s = 1/3, Var s = 1/18, and the
/// fraction inside half the disc's area is 2·½ − ¼ = ¾ (binomial variance 3/16). Each checked
/// to 5 standard errors of its estimate (fixed seeds). The same u gives a smaller radius than by
/// area (√(1 − √(1 − u)) ≤ √u), at the same angle, so the two draws of one particle share a
/// direction.
#[test]
fn a_disc_weighted_by_pipe_flux_has_poiseuilles_moments() {
    use pseudorigid::population::sampling::{DiscWeight, disc_point};
    use pseudorigid::tensor::Vec3;
    let n = 20_000;
    let (centre, normal, radius) = (Vec3::new(1.0, -2.0, 0.5), Vec3::new(0.0, 1.0, 1.0), 2.0);
    let unit = normal.normalize();
    let (mut s1, mut s2, mut inner) = (0.0, 0.0, 0.0);
    for k in 0..n {
        let p = disc_point(
            &mut particle_rng(5, k),
            &centre,
            &normal,
            radius,
            DiscWeight::Poiseuille,
        )
        .unwrap();
        let q = disc_point(&mut particle_rng(5, k), &centre, &normal, radius, DiscWeight::Area).unwrap();
        let (d, e) = (p - centre, q - centre);
        assert!(d.dot(&unit).abs() <= 1e-14 * radius && d.norm() <= e.norm() * (1.0 + 1e-15));
        assert!(d.norm() == 0.0 || (d.normalize() - e.normalize()).norm() <= 1e-12);
        let s = d.norm_squared() / (radius * radius);
        s1 += s;
        s2 += (s - 1.0 / 3.0).powi(2);
        inner += f64::from(u8::from(s <= 0.5));
    }
    let n_f = n as f64;
    assert!(
        (s1 / n_f - 1.0 / 3.0).abs() <= 5.0 * (1.0 / 18.0 / n_f).sqrt(),
        "{}",
        s1 / n_f
    );
    // Var s = 1/18; (s − 1/3)² has variance E(s − 1/3)⁴ − 1/18² = 1/135 − 1/324 (density 2(1 − s)).
    let var4 = 1.0 / 135.0 - 1.0 / 324.0;
    assert!(
        (s2 / n_f - 1.0 / 18.0).abs() <= 5.0 * (var4 / n_f).sqrt(),
        "{}",
        s2 / n_f
    );
    assert!(
        (inner / n_f - 0.75).abs() <= 5.0 * (3.0 / 16.0 / n_f).sqrt(),
        "{}",
        inner / n_f
    );
}

/// The injection draws: disc points lie on the disc with ρ²/R² uniform on [0, 1) and no
/// preferred direction; rotations are rotations with the moments of the Haar measure (each
/// entry Q_ij is a coordinate of a uniform unit vector: mean 0, E[Q_ij²] = 1/3, E[Q_ij⁴] = 1/5).
/// Each mean is checked to 5 standard errors of its estimate (the seeds are fixed, so the
/// test is deterministic; 5σ leaves room for any seed).
#[test]
fn disc_and_rotation_draws_have_the_right_moments() {
    use pseudorigid::population::sampling::{haar_rotation, uniform_disc};
    use pseudorigid::tensor::{Mat3, Vec3};
    let n = 20_000;
    let (centre, normal, radius) = (Vec3::new(1.0, -2.0, 0.5), Vec3::new(1.0, 1.0, 0.0), 2.0);
    let unit = normal.normalize();
    let (mut rho2, mut offset) = (0.0, Vec3::zeros());
    for k in 0..n {
        let p = uniform_disc(&mut particle_rng(11, k), &centre, &normal, radius).unwrap();
        let d = p - centre;
        // In the plane and inside the disc, to round-off of |d| ≤ R.
        assert!(d.dot(&unit).abs() <= 1e-14 * radius && d.norm() <= radius * (1.0 + 1e-15));
        rho2 += d.norm_squared() / (radius * radius);
        offset += d;
    }
    let n_f = n as f64;
    // ρ²/R² uniform: mean 1/2, variance 1/12.
    assert!((rho2 / n_f - 0.5).abs() <= 5.0 * (1.0 / 12.0 / n_f).sqrt());
    // Each in-plane coordinate has variance R²/4 (in-plane directions), 0 along the normal.
    assert!((offset / n_f).amax() <= 5.0 * radius / 2.0 / n_f.sqrt());
    assert!(uniform_disc(&mut particle_rng(1, 1), &centre, &Vec3::zeros(), 1.0).is_err());
    assert!(uniform_disc(&mut particle_rng(1, 1), &centre, &normal, -1.0).is_err());

    let (mut m1, mut m2) = (Mat3::zeros(), Mat3::zeros());
    for k in 0..n {
        let q = haar_rotation(&mut particle_rng(12, k));
        // Orthonormal with det 1 to round-off of a 3×3 product.
        assert!((q.transpose() * q - Mat3::identity()).amax() <= 1e-14 && (q.determinant() - 1.0).abs() <= 1e-14);
        m1 += q;
        m2 += q.component_mul(&q);
    }
    assert!((m1 / n_f).amax() <= 5.0 * (1.0 / 3.0 / n_f).sqrt());
    assert!((m2 / n_f).add_scalar(-1.0 / 3.0).amax() <= 5.0 * (4.0 / 45.0 / n_f).sqrt());
}

/// The composite boundary: planes first (indices 0..P), then the other boundary's patches
/// shifted by P; the nearer decides, a tie goes to the plane, a NaN gap is passed on.
#[test]
fn composite_boundary_indices_rules_and_ties() {
    use pseudorigid::contact::{Boundary, Composite, Extent, PatchRule, PipeWall, Plane, Planes};
    use pseudorigid::tensor::Vec3;
    let plane = |name: &str, x: f64, sign: f64, rule| Plane {
        name: name.to_string(),
        point: Vec3::new(x, 0.0, 0.0),
        normal: Vec3::x() * sign,
        rule,
    };
    let planes = Planes::new(vec![
        plane("inlet", 0.0, -1.0, PatchRule::Stick),
        plane("outlet", 10.0, 1.0, PatchRule::Exit),
    ])
    .unwrap();
    let b = Composite::new(planes, PipeWall::new(2.0).unwrap());
    let point = Extent::Point { radius: 0.5 };
    let names: Vec<_> = (0..3).map(|p| (b.patch_name(p), b.rule(p))).collect();
    assert_eq!(
        names,
        [
            ("inlet", PatchRule::Stick),
            ("outlet", PatchRule::Exit),
            ("wall", PatchRule::Stick)
        ]
    );
    // Near the outlet: gap 10 − 9.8 − 0.5 = −0.3 to the outlet, 2 − 0 − 0.5 = 1.5 to the wall.
    let g = b.nearest(&Vec3::new(9.8, 0.0, 0.0), &point);
    assert_eq!(g.patch, 1);
    assert!((g.gap + 0.3).abs() <= 1e-15 * 10.0);
    // Near the wall mid-pipe: the wall's patch 0 becomes 2.
    let g = b.nearest(&Vec3::new(5.0, 1.2, 0.0), &point);
    assert_eq!((g.patch, g.normal), (2, Vec3::y()));
    // Equal gaps 1.5 to the inlet (x = 2) and to the wall: the plane wins.
    assert_eq!(b.nearest(&Vec3::new(2.0, 0.0, 0.0), &point).patch, 0);
    assert!(b.nearest(&Vec3::new(f64::NAN, 0.0, 0.0), &point).gap.is_nan());
    assert!(b.nearest(&Vec3::new(5.0, f64::NAN, 0.0), &point).gap.is_nan());
}

proptest::proptest! {
    /// Any finite f64 (every bit pattern: subnormals, extremes, −0) survives the result file's
    /// JSON bit for bit (shortest round-trip printing, `float_roundtrip` parsing).
    #[test]
    fn any_finite_f64_round_trips_through_a_record(bits in proptest::collection::vec(proptest::num::u64::ANY, 25)) {
        use pseudorigid::driver::RunStats;
        use pseudorigid::particle::State;
        use pseudorigid::population::ParticleRecord;
        use pseudorigid::tensor::{Mat3, Vec3};
        let v: Vec<f64> = bits.iter().map(|&b| f64::from_bits(b)).map(|x| if x.is_finite() { x } else { 1.0 }).collect();
        let state = State {
            t: v[0],
            x: Vec3::from_column_slice(&v[1..4]),
            v: Vec3::from_column_slice(&v[4..7]),
            f: Mat3::from_column_slice(&v[7..16]),
            a: Mat3::from_column_slice(&v[16..25]),
        };
        let record = ParticleRecord::<NeoHooke> {
            index: bits[0],
            spec: None,
            fate: Fate::Deposited { patch: 3, position: state.x, time: state.t },
            end: Some(state),
            stats: RunStats::default(),
            integrator: Default::default(),
            samples: vec![state],
            observed: serde_json::Value::Null,
        };
        let back: ParticleRecord<NeoHooke> = serde_json::from_slice(&serde_json::to_vec(&record).unwrap()).unwrap();
        let end = back.end.unwrap();
        let got: Vec<u64> = std::iter::once(end.t)
            .chain(end.x.iter().copied())
            .chain(end.v.iter().copied())
            .chain(end.f.iter().copied())
            .chain(end.a.iter().copied())
            .map(f64::to_bits)
            .collect();
        let want: Vec<u64> = v.iter().map(|x| x.to_bits()).collect();
        proptest::prop_assert_eq!(got, want);
    }
}

/// A record's observer summary reads back as the type its watch kept it in, through a
/// checkpoint's JSON; a record without one, or with a summary of another shape, is a
/// `SummaryError` naming the particle, never a default value.
#[test]
fn an_observer_summary_reads_back_typed_or_names_the_particle() {
    use pseudorigid::driver::RunStats;
    use pseudorigid::population::ParticleRecord;
    use pseudorigid::population::release::{Peak, Released};
    #[derive(Debug, PartialEq, serde::Serialize, serde::Deserialize)]
    struct Deepest {
        generation: u8,
    }
    let record = |observed: serde_json::Value| {
        let record = ParticleRecord::<NeoHooke> {
            index: 17,
            spec: None,
            fate: Fate::Suspended,
            end: None,
            stats: RunStats::default(),
            integrator: Default::default(),
            samples: vec![],
            observed,
        };
        serde_json::from_slice::<ParticleRecord<NeoHooke>>(&serde_json::to_vec(&record).unwrap()).unwrap()
    };
    let kept = record(serde_json::to_value(Deepest { generation: 5 }).unwrap());
    assert_eq!(kept.summary::<Deepest>().unwrap(), Deepest { generation: 5 });
    let other = kept.summary::<Released>().unwrap_err();
    assert_eq!(other.index, 17);
    assert!(other.summary.ends_with("Released"), "{other}");
    let none = record(serde_json::Value::Null).summary::<Deepest>().unwrap_err();
    assert_eq!((none.index, none.reason.as_str()), (17, "none kept"));
    // The release observer's own summary, as it keeps it.
    let released = Released {
        peak: Peak { t: 0.25, value: 1.5 },
        crossings: vec![None],
    };
    let back = record(serde_json::to_value(&released).unwrap())
        .summary::<Released>()
        .unwrap();
    assert_eq!(back, released);
}
