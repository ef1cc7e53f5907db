//! The NumPy/SciPy peer of the inertialess model, run as a subprocess.
//!
//! `benches/peers/inertialess.py` integrates the inertialess shape equation Ḟ = l_s F, with
//! l_s from dev σ̃(l_s) = dev σ_el(F), tr l_s = 0 (the Θ → 0 limit of paper eq. 18 with the
//! Neo-Hooke stress of eq. 9 and the Jeffery–Roscoe traction of eq. 12), in simple shear
//! u = (y, 0, 0), using `scipy.integrate.solve_ivp`. It is written from the paper, not ported from
//! this crate, so agreement between the two checks both; the work-precision study also times it
//! as the baseline a Python prototype gives.
//!
//! The interpreter is `python3`, or the program named by the environment variable
//! `PSEUDORIGID_PYTHON`; its packages are pinned in `benches/peers/requirements.txt`. A missing
//! interpreter or missing SciPy is [`ScipyPeerError::Unavailable`], so callers can skip the peer.

use crate::tensor::Mat3;
use serde::Deserialize;
use std::io::Read;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};
use thiserror::Error;

/// Environment variable naming the Python interpreter (default `python3`).
pub const PYTHON_ENV: &str = "PSEUDORIGID_PYTHON";

/// SciPy's ODE method used by the peer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PeerMethod {
    /// `solve_ivp(method="Radau")`: Radau IIA of order 5, finite-difference Jacobian.
    Radau,
    /// `solve_ivp(method="LSODA")`: ODEPACK's Adams/BDF switching multistep method.
    Lsoda,
    /// `solve_ivp(method="DOP853")`: explicit Runge–Kutta of order 8, for high-accuracy
    /// references of non-stiff cases (Ca ≳ 0.1).
    Dop853,
}

impl PeerMethod {
    /// Integrator name in the work-precision dataset.
    pub fn integrator(self) -> &'static str {
        match self {
            PeerMethod::Radau => "scipy_radau",
            PeerMethod::Lsoda => "scipy_lsoda",
            PeerMethod::Dop853 => "scipy_dop853",
        }
    }

    fn scipy_name(self) -> &'static str {
        match self {
            PeerMethod::Radau => "Radau",
            PeerMethod::Lsoda => "LSODA",
            PeerMethod::Dop853 => "DOP853",
        }
    }
}

/// The problem the peer solves: a stress-free ellipsoid with axes along the shear axes, F(0) = 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeerCase {
    /// Relative semi-axes along flow, gradient and vorticity (the peer scales them to d_eq = 1).
    pub semi_axes: [f64; 3],
    /// Capillary number Ca = μ_f γ̇ / μ_s.
    pub ca: f64,
    /// λ_s / μ_s.
    pub bulk_ratio: f64,
    /// End time in units of 1/γ̇; F is sampled at t = 1, 2, … below it and at t_end.
    pub t_end: f64,
}

/// One peer run: SciPy's work statistics and the sampled deformation gradient.
#[derive(Debug, Clone, PartialEq)]
pub struct PeerRun {
    /// Accepted steps.
    pub steps: u64,
    /// Model evaluations, one per state, including the finite-difference Jacobian columns.
    pub rhs_evals: u64,
    /// Jacobian evaluations reported by SciPy.
    pub jac_evals: u64,
    /// Wall time of `solve_ivp` alone, measured by the peer (no interpreter start-up).
    pub wall_s: f64,
    /// (t, F(t)) at the output times, F from SciPy's dense output.
    pub samples: Vec<(f64, Mat3)>,
}

/// Failures of a peer run.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ScipyPeerError {
    /// The interpreter cannot be started or lacks NumPy/SciPy.
    #[error(
        "SciPy peer unavailable: `{python}` {reason} (install with `pip install -r benches/peers/requirements.txt`, or set {PYTHON_ENV})"
    )]
    Unavailable {
        /// Interpreter tried.
        python: String,
        /// What went wrong.
        reason: String,
    },
    /// The peer ran but reported failure (SciPy's message or Python's error output).
    #[error("SciPy peer {method} at rtol {rtol:e} failed ({status}): {message}")]
    Failed {
        /// SciPy method.
        method: &'static str,
        /// Relative tolerance.
        rtol: f64,
        /// Exit status.
        status: String,
        /// Diagnostic text.
        message: String,
    },
    /// The peer did not finish within the time limit and was killed.
    #[error("SciPy peer {method} at rtol {rtol:e} still running after {limit_s} s; killed")]
    TimedOut {
        /// SciPy method.
        method: &'static str,
        /// Relative tolerance.
        rtol: f64,
        /// Time limit in seconds.
        limit_s: u64,
    },
    /// The peer's output is not the expected JSON line.
    #[error("SciPy peer output unreadable: {reason}")]
    BadOutput {
        /// Parse or consistency failure.
        reason: String,
    },
}

/// How to start the peer: interpreter, script and a wall-clock limit per run.
#[derive(Debug, Clone, PartialEq)]
pub struct Peer {
    /// Python interpreter.
    pub python: String,
    /// Path of `inertialess.py`.
    pub script: PathBuf,
    /// A run still going after this long is killed ([`ScipyPeerError::TimedOut`]).
    pub time_limit: Duration,
}

/// Interval at which a running peer is polled for completion.
const POLL: Duration = Duration::from_millis(20);

impl Peer {
    /// The interpreter from [`PYTHON_ENV`] (default `python3`) and the script shipped in
    /// `benches/peers/` of this source tree; ten minutes per run, far above the slowest run of
    /// the study (Radau at rtol 1e-13, under a minute).
    pub fn from_env() -> Self {
        Self {
            python: std::env::var(PYTHON_ENV).unwrap_or_else(|_| "python3".into()),
            script: PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/benches/peers/inertialess.py")),
            time_limit: Duration::from_secs(600),
        }
    }

    /// Check that the interpreter starts and imports NumPy and SciPy, and that the script exists.
    pub fn check(&self) -> Result<(), ScipyPeerError> {
        let unavailable = |reason: String| ScipyPeerError::Unavailable {
            python: self.python.clone(),
            reason,
        };
        if !self.script.is_file() {
            return Err(unavailable(format!("has no script at {}", self.script.display())));
        }
        let out = Command::new(&self.python)
            .args(["-c", "import numpy, scipy.integrate, scipy.special"])
            .output()
            .map_err(|e| unavailable(format!("cannot be started: {e}")))?;
        if out.status.success() {
            Ok(())
        } else {
            // The last line of Python's traceback names the missing module.
            let stderr = String::from_utf8_lossy(&out.stderr);
            let last = stderr.lines().rev().find(|l| !l.trim().is_empty()).unwrap_or("");
            Err(unavailable(format!("cannot import numpy/scipy: {}", last.trim())))
        }
    }

    /// Run `case` with `method` at rtol = atol = `tol`.
    pub fn run(&self, case: &PeerCase, method: PeerMethod, tol: f64) -> Result<PeerRun, ScipyPeerError> {
        let tol_s = format!("{tol:e}");
        self.invoke(case, method, tol, &["--rtol", &tol_s, "--atol", &tol_s])
    }

    /// The peer's high-accuracy run: `method` at rtol = atol = 1e-13.
    pub fn reference(&self, case: &PeerCase, method: PeerMethod) -> Result<PeerRun, ScipyPeerError> {
        self.invoke(case, method, 1e-13, &["--reference"])
    }

    fn invoke(
        &self,
        case: &PeerCase,
        method: PeerMethod,
        rtol: f64,
        extra: &[&str],
    ) -> Result<PeerRun, ScipyPeerError> {
        let [a, b, c] = case.semi_axes;
        let mut child = Command::new(&self.python)
            .arg(&self.script)
            .args(["--axes", &format!("{a:e},{b:e},{c:e}")])
            .args(["--ca", &format!("{:e}", case.ca)])
            .args(["--bulk-ratio", &format!("{:e}", case.bulk_ratio)])
            .args(["--t-end", &format!("{:e}", case.t_end)])
            .args(["--method", method.scipy_name()])
            .args(extra)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| ScipyPeerError::Unavailable {
                python: self.python.clone(),
                reason: format!("cannot be started: {e}"),
            })?;
        // Drain both pipes on their own threads so a chatty peer cannot block on a full pipe.
        let stdout = drain(child.stdout.take());
        let stderr = drain(child.stderr.take());
        let start = Instant::now();
        let status = loop {
            match child.try_wait() {
                Ok(Some(status)) => break status,
                Ok(None) if start.elapsed() < self.time_limit => std::thread::sleep(POLL),
                Ok(None) => {
                    // Already exited or unkillable: either way the run is abandoned.
                    let _ = child.kill();
                    let _ = child.wait();
                    return Err(ScipyPeerError::TimedOut {
                        method: method.scipy_name(),
                        rtol,
                        limit_s: self.time_limit.as_secs(),
                    });
                }
                Err(e) => {
                    return Err(ScipyPeerError::Failed {
                        method: method.scipy_name(),
                        rtol,
                        status: "wait failed".into(),
                        message: e.to_string(),
                    });
                }
            }
        };
        let stdout = stdout.join().unwrap_or_default();
        let stderr = stderr.join().unwrap_or_default();
        if !status.success() {
            return Err(ScipyPeerError::Failed {
                method: method.scipy_name(),
                rtol,
                status: status.to_string(),
                message: format!("{} {}", stdout.trim(), stderr.trim()),
            });
        }
        parse(&stdout)
    }
}

fn drain(pipe: Option<impl Read + Send + 'static>) -> std::thread::JoinHandle<String> {
    std::thread::spawn(move || {
        let mut text = String::new();
        if let Some(mut p) = pipe {
            // A read error leaves the text read so far; the JSON check reports what is missing.
            let _ = p.read_to_string(&mut text);
        }
        text
    })
}

/// The peer's JSON line (fields not needed here are ignored).
#[derive(Deserialize)]
struct Output {
    steps: u64,
    rhs_evals: u64,
    jac_evals: u64,
    wall_s: f64,
    t_samples: Vec<f64>,
    f_samples: Vec<[f64; 9]>,
}

fn parse(stdout: &str) -> Result<PeerRun, ScipyPeerError> {
    let bad = |reason: String| ScipyPeerError::BadOutput { reason };
    let line = stdout.lines().last().unwrap_or("");
    let out: Output = serde_json::from_str(line).map_err(|e| bad(format!("{e} in {line:.200}")))?;
    if out.t_samples.len() != out.f_samples.len() || out.t_samples.is_empty() {
        return Err(bad(format!(
            "{} output times but {} samples of F",
            out.t_samples.len(),
            out.f_samples.len()
        )));
    }
    if let Some((t, _)) = out
        .t_samples
        .iter()
        .zip(&out.f_samples)
        .find(|(t, f)| !t.is_finite() || f.iter().any(|v| !v.is_finite()))
    {
        return Err(bad(format!("non-finite sample at t = {t}")));
    }
    if !(out.wall_s.is_finite() && out.wall_s >= 0.0) {
        return Err(bad(format!("wall time {}", out.wall_s)));
    }
    Ok(PeerRun {
        steps: out.steps,
        rhs_evals: out.rhs_evals,
        jac_evals: out.jac_evals,
        wall_s: out.wall_s,
        samples: out
            .t_samples
            .iter()
            .zip(&out.f_samples)
            .map(|(&t, f)| (t, Mat3::from_row_slice(f)))
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_row_major_samples() {
        let line = r#"{"method": "Radau", "steps": 3, "rhs_evals": 40, "nfev": 30, "jac_evals": 1,
            "wall_s": 0.5, "t_samples": [1.0], "f_samples": [[1, 2, 3, 4, 5, 6, 7, 8, 9]]}"#
            .replace('\n', " ");
        let run = parse(&format!("warning on an earlier line\n{line}\n")).unwrap();
        assert_eq!((run.steps, run.rhs_evals, run.jac_evals), (3, 40, 1));
        assert_eq!(run.samples[0].1[(0, 2)], 3.0);
        assert_eq!(run.samples[0].1[(2, 0)], 7.0);
    }

    #[test]
    fn rejects_inconsistent_or_non_finite_output() {
        let short = r#"{"steps": 1, "rhs_evals": 1, "jac_evals": 0, "wall_s": 0.1, "t_samples": [1.0, 2.0], "f_samples": [[1,0,0,0,1,0,0,0,1]]}"#;
        assert!(matches!(parse(short), Err(ScipyPeerError::BadOutput { .. })));
        let nan = r#"{"steps": 1, "rhs_evals": 1, "jac_evals": 0, "wall_s": 0.1, "t_samples": [1.0], "f_samples": [[1,0,0,0,1,0,0,0,NaN]]}"#;
        assert!(matches!(parse(nan), Err(ScipyPeerError::BadOutput { .. })));
        assert!(matches!(parse("Traceback ..."), Err(ScipyPeerError::BadOutput { .. })));
    }

    #[test]
    fn missing_interpreter_is_unavailable() {
        let peer = Peer {
            python: "/nonexistent/python-for-pseudorigid-test".into(),
            ..Peer::from_env()
        };
        assert!(matches!(peer.check(), Err(ScipyPeerError::Unavailable { .. })));
    }
}
