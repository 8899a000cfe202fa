//! `translucid-fuzz`: a fuzzer for translucid's glTF import that runs on stable Rust with no
//! tools beyond cargo. Seeds from the corpus are mutated (structurally through their JSON,
//! and as raw bytes) and each mutant is loaded in a child process, so that panics, aborts,
//! crashes, hangs and memory blow-ups are observed instead of ending the run.

mod child;
mod corpus;
mod fuzz;
mod glb;
mod mutate;
mod report;
mod rng;
mod runner;

use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Duration;

/// Failed allocations print where they happened before Rust aborts (see `child`).
#[global_allocator]
static ALLOCATOR: child::ReportingAllocator = child::ReportingAllocator;

#[derive(Parser)]
#[command(
    name = "translucid-fuzz",
    version,
    about = "Fuzzes translucid's glTF import"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Mutates the corpus's glTF files and loads each mutant in a child process, for the
    /// given time; exits non-zero if any mutant made the child panic, crash, hang or run out
    /// of memory.
    Gltf(GltfArgs),
    /// Loads one file as a child does, and with --render renders it (exit 0: loaded and, with
    /// --render, right; 2: clean error, 3: a panic the library caught, 4: a NaN or infinite
    /// pixel or exact off the reference; anything else is a finding).
    #[command(hide = true)]
    RunOne {
        path: PathBuf,
        #[arg(long)]
        render: bool,
    },
}

#[derive(clap::Args)]
struct GltfArgs {
    /// How long to fuzz.
    #[arg(long, default_value_t = 60)]
    seconds: u64,
    /// Runs cases 0 to N-1 of --seed instead, however long they take: a fixed run, as the
    /// tests make.
    #[arg(long, conflicts_with = "case")]
    cases: Option<u64>,
    /// Makes the run reproducible: case N is built from (seed, N) alone [default: the time].
    #[arg(long)]
    seed: Option<u64>,
    /// A folder (searched recursively) or file of seed .gltf/.glb files; repeatable
    /// [default: assets/scenes].
    #[arg(long)]
    corpus: Vec<PathBuf>,
    /// Where findings are saved, one folder each [default: target/fuzz-findings].
    #[arg(long)]
    out: Option<PathBuf>,
    /// Cases run in parallel.
    #[arg(long, default_value_t = 2)]
    jobs: usize,
    /// Only load each mutant: do not render what loads with every method (a case then takes
    /// milliseconds, not seconds).
    #[arg(long)]
    load_only: bool,
    /// A child running longer is killed and counted as a hang [default: 10, 120 when
    /// rendering].
    #[arg(long)]
    timeout: Option<u64>,
    /// The child's address-space cap (RLIMIT_AS), in MiB.
    #[arg(long, default_value_t = 4096)]
    memory_mib: u64,
    /// Runs only case N of --seed (with the same --corpus), to reproduce a finding.
    #[arg(long)]
    case: Option<u64>,
}

/// The workspace this was built in: defaults are relative to it, so that they hold from
/// any working directory.
fn workspace() -> PathBuf {
    let built = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    if built.join("assets/scenes").is_dir() {
        built.canonicalize().unwrap_or(built)
    } else {
        PathBuf::from(".")
    }
}

fn main() -> ExitCode {
    match Cli::parse().command {
        Command::RunOne { path, render } => child::run_one(&path, render),
        Command::Gltf(args) => {
            let root = workspace();
            let target = root.join("target");
            let seed = args.seed.unwrap_or_else(|| {
                std::time::SystemTime::now()
                    .duration_since(std::time::UNIX_EPOCH)
                    .map_or(0, |d| d.as_nanos() as u64)
            });
            let options = fuzz::Options {
                seconds: args.seconds,
                cases: args.cases,
                seed,
                corpus: if args.corpus.is_empty() {
                    vec![root.join("assets/scenes")]
                } else {
                    args.corpus
                },
                out: args.out.unwrap_or_else(|| target.join("fuzz-findings")),
                jobs: args.jobs,
                limits: runner::Limits {
                    timeout: Duration::from_secs(args.timeout.unwrap_or(if args.load_only {
                        10
                    } else {
                        120
                    })),
                    memory: args.memory_mib << 20,
                    render: !args.load_only,
                },
                case: args.case,
                work: target.join(format!("fuzz-work/{}", std::process::id())),
            };
            match fuzz::run(&options) {
                Ok(false) => ExitCode::SUCCESS,
                Ok(true) => ExitCode::from(1),
                Err(e) => {
                    eprintln!("translucid-fuzz: {e}");
                    ExitCode::from(2)
                }
            }
        }
    }
}
