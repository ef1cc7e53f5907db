//! Progress of a run: a bar with rate and ETA on a terminal, plain log lines on stderr at a
//! fixed interval otherwise (batch schedulers keep stderr in a file, where a redrawn bar is
//! noise), or nothing.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

/// How a run reports its progress.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Progress {
    /// A bar when stderr is a terminal, otherwise log lines every [`LOG_INTERVAL`].
    Auto,
    /// An `indicatif` bar on stderr.
    Bar,
    /// A log line on stderr every `interval` and at the end.
    Log {
        /// Time between lines.
        interval: Duration,
    },
    /// Nothing (tests).
    Quiet,
}

/// Interval of the log lines of [`Progress::Auto`] off a terminal.
pub const LOG_INTERVAL: Duration = Duration::from_secs(30);

/// `done/total (percent), rate, ETA` of a run that has finished `done` of `total` particles,
/// `fresh` of them in `elapsed` (the rest came from a checkpoint).
pub fn progress_line(label: &str, done: u64, total: u64, fresh: u64, elapsed: Duration) -> String {
    let percent = if total == 0 {
        100.0
    } else {
        100.0 * done as f64 / total as f64
    };
    let seconds = elapsed.as_secs_f64();
    let rate = if seconds > 0.0 { fresh as f64 / seconds } else { 0.0 };
    let eta = if done >= total {
        "0s".to_string()
    } else if rate > 0.0 {
        format_duration((total - done) as f64 / rate)
    } else {
        "unknown".to_string()
    };
    format!("{label}: {done}/{total} particles ({percent:.1} %), {rate:.1} particles/s, ETA {eta}")
}

/// `1h02m03s`, `4m05s` or `6s` (rounded to seconds).
fn format_duration(seconds: f64) -> String {
    // Beyond ~3e10 years the ETA says nothing anyway; the cap keeps the cast exact.
    let s = seconds.round().clamp(0.0, 1e18) as u64;
    match (s / 3600, s / 60 % 60, s % 60) {
        (0, 0, sec) => format!("{sec}s"),
        (0, min, sec) => format!("{min}m{sec:02}s"),
        (h, min, sec) => format!("{h}h{min:02}m{sec:02}s"),
    }
}

/// The reporter a run drives.
pub(crate) enum Reporter {
    Bar(ProgressBar),
    Log {
        label: String,
        interval: Duration,
        next: Instant,
        total: u64,
        resumed: u64,
        started: Instant,
    },
    Quiet,
}

impl Reporter {
    /// Start reporting a run of `total` particles of which `resumed` are already done.
    pub(crate) fn start(progress: Progress, label: &str, total: u64, resumed: u64) -> Self {
        let progress = match progress {
            Progress::Auto if std::io::stderr().is_terminal() => Progress::Bar,
            Progress::Auto => Progress::Log { interval: LOG_INTERVAL },
            other => other,
        };
        let now = Instant::now();
        match progress {
            Progress::Bar => {
                let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
                // The template is a constant; a bad one would be a bug caught by any run.
                if let Ok(style) = ProgressStyle::with_template(
                    "{prefix}: [{elapsed_precise}] {wide_bar} {pos}/{len} ({per_sec}, ETA {eta})",
                ) {
                    bar.set_style(style);
                }
                bar.set_prefix(label.to_string());
                bar.set_position(resumed);
                // Rate and ETA from this run's particles only, not the resumed ones.
                bar.reset_eta();
                Reporter::Bar(bar)
            }
            Progress::Log { interval } => Reporter::Log {
                label: label.to_string(),
                interval,
                next: now + interval,
                total,
                resumed,
                started: now,
            },
            Progress::Quiet | Progress::Auto => Reporter::Quiet,
        }
    }

    /// The time until the next log line is due (`None`: no deadline).
    pub(crate) fn until_due(&self) -> Option<Duration> {
        match self {
            // A zero interval prints a line per record; waking up for it would spin.
            Reporter::Log { interval, .. } if interval.is_zero() => None,
            Reporter::Log { next, .. } => Some(next.saturating_duration_since(Instant::now())),
            Reporter::Bar(_) | Reporter::Quiet => None,
        }
    }

    /// `done` particles are finished.
    pub(crate) fn update(&mut self, done: u64) {
        match self {
            Reporter::Bar(bar) => bar.set_position(done),
            Reporter::Log {
                label,
                interval,
                next,
                total,
                resumed,
                started,
            } => {
                let now = Instant::now();
                if now >= *next {
                    eprintln!(
                        "{}",
                        progress_line(label, done, *total, done.saturating_sub(*resumed), started.elapsed())
                    );
                    *next = now + *interval;
                }
            }
            Reporter::Quiet => {}
        }
    }

    /// The run is over with `done` particles finished.
    pub(crate) fn finish(self, done: u64) {
        match self {
            Reporter::Bar(bar) => {
                bar.set_position(done);
                bar.finish();
            }
            Reporter::Log {
                label,
                total,
                resumed,
                started,
                ..
            } => eprintln!(
                "{}",
                progress_line(&label, done, total, done.saturating_sub(resumed), started.elapsed())
            ),
            Reporter::Quiet => {}
        }
    }
}

/// CPU time (user + system) of this process in seconds, where the system says (Linux: fields
/// 14 and 15 of /proc/self/stat, in USER_HZ = 100 ticks per second, fixed for user space). It
/// does not depend on the machine's load, unlike wall time.
pub fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The command name (field 2) is in parentheses and may hold spaces: count after it.
    let rest = stat.get(stat.rfind(')')? + 2..)?;
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: f64 = fields.get(11)?.parse::<f64>().ok()? + fields.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

/// Resident set size of this process in bytes, where the system says (Linux: VmRSS of
/// /proc/self/status).
pub fn process_resident_bytes() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmRSS:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024.0)
}
