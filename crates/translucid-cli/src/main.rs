//! `translucid`: render, compare against the CPU reference, check glTF files, benchmark, and
//! list devices.

mod commands;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "translucid",
    version,
    about = "Exact order-independent transparency on Vulkan"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// A frame size written WIDTHxHEIGHT.
#[derive(Clone, Copy, Debug)]
pub struct Size {
    pub width: u32,
    pub height: u32,
}

impl std::str::FromStr for Size {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let (w, h) = s
            .split_once(['x', 'X'])
            .ok_or_else(|| format!("size {s:?} is not WIDTHxHEIGHT"))?;
        let parse = |v: &str| {
            v.trim()
                .parse::<u32>()
                .map_err(|e| format!("size {s:?}: {e}"))
        };
        Ok(Self {
            width: parse(w)?,
            height: parse(h)?,
        })
    }
}

/// Settings of the `wavelet` method (other methods ignore them).
#[derive(clap::Args, Clone, Copy, Debug)]
pub struct WaveletArgs {
    /// wavelet: Haar rank 0 to 3 (2^(rank+1) coefficients per colour channel) [default: 3]
    #[arg(long)]
    pub rank: Option<u32>,
    /// wavelet: depth noise strength in cells (0: off)
    #[arg(long, default_value_t = 0.0)]
    pub noise: f32,
    /// wavelet: storage precision of the coefficients
    #[arg(long, value_enum, default_value_t = Precision::Half)]
    pub precision: Precision,
    /// wavelet: where the coefficients live: registers, on the bins exact's raster reads too,
    /// or full-screen images
    #[arg(long, value_enum, default_value_t = Storage::Bins)]
    pub storage: Storage,
}

/// What changes between a bench's frames.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// The camera circles the scene and every third transparent draw moves, every frame.
    Orbit,
    /// The same frame again and again.
    Static,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Storage {
    Bins,
    Images,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    Half,
    Single,
}

#[derive(Subcommand)]
enum Command {
    /// List Vulkan devices with the limits translucid sizes itself by.
    Info,
    /// Render a scene with one method and write a PNG.
    Render {
        /// A glTF path or a generated scene's name (boxes, spheres, particles, planes, ...).
        scene: String,
        /// blend, exact, wavelet or wboit
        #[arg(long, short, default_value = "exact")]
        method: String,
        /// exact: stop a pixel once its transmittance is under T in every channel (0: exact).
        #[arg(long, default_value_t = 0.0)]
        threshold: f32,
        #[command(flatten)]
        wavelet: WaveletArgs,
        #[arg(long, default_value = "1280x720")]
        size: Size,
        #[arg(short, long, default_value = "out/render.png")]
        output: PathBuf,
        /// Render the frame a second time and print that warm frame's stage times: the
        /// first frame's include building pipelines and compiling shaders.
        #[arg(long)]
        warm: bool,
    },
    /// Render with a method and with the CPU reference, and measure the difference.
    Compare {
        scene: String,
        /// blend, exact, wavelet or wboit
        #[arg(long, short, default_value = "exact")]
        method: String,
        /// exact: stop a pixel once its transmittance is under T in every channel (0: exact).
        #[arg(long, default_value_t = 0.0)]
        threshold: f32,
        #[command(flatten)]
        wavelet: WaveletArgs,
        #[arg(long, default_value = "640x360")]
        size: Size,
        /// Write method | reference | error heat map side by side.
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Check that translucid renders glTF files right, each within 2/255 of what its method
    /// promises.
    ///
    /// Each file is rendered with the method and measured against an image computed on the
    /// CPU from the same opaque layer: the CPU reference (exact, blend) or the method's CPU
    /// model (wavelet, wboit). A file passes when no channel of any pixel is off by more than
    /// 2/255 (a NaN fails).
    ///
    /// Exits non-zero when a file cannot be loaded or rendered, when no glTF file is found,
    /// or when a file fails with exact, wavelet or wboit. blend (unsorted alpha blending) is
    /// right only when draws happen to be sorted: its rows show its error against the
    /// reference, but image errors never make the run fail.
    Conformance {
        /// Folders (searched recursively for .gltf and .glb files) or glTF files.
        #[arg(required = true)]
        paths: Vec<PathBuf>,
        /// blend, exact, wavelet or wboit (blend's image errors never fail the run)
        #[arg(long, short, default_value = "exact")]
        method: String,
        /// exact: stop a pixel once its transmittance is under T in every channel (0: exact);
        /// checked against the reference with the same early stop.
        #[arg(long, default_value_t = 0.0)]
        threshold: f32,
        #[command(flatten)]
        wavelet: WaveletArgs,
        #[arg(long, default_value = "480x270")]
        size: Size,
        /// Print one JSON document instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Median GPU time per stage over N frames, with the ratio to `blend` from the same run.
    Bench {
        #[arg(required = true)]
        scenes: Vec<String>,
        #[arg(long = "method", short, default_value = "exact")]
        methods: Vec<String>,
        /// exact: stop a pixel once its transmittance is under T in every channel (0: exact).
        #[arg(long, default_value_t = 0.0)]
        threshold: f32,
        #[command(flatten)]
        wavelet: WaveletArgs,
        #[arg(long, default_value = "1280x720")]
        size: Size,
        #[arg(long, default_value_t = 20)]
        frames: u32,
        /// What changes from frame to frame, as in an engine's frame loop; `orbit,static`
        /// runs both, taking turns, and reports moving over static from the same run.
        #[arg(long, value_enum, value_delimiter = ',', default_value = "orbit")]
        motion: Vec<Motion>,
        /// Print one JSON object per (scene, method) line instead of a table.
        #[arg(long)]
        json: bool,
    },
}

fn main() -> ExitCode {
    // The library's warnings (parts of a file it skips or cannot draw as written) on stderr;
    // RUST_LOG sets another level.
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn"))
        .format_timestamp(None)
        .init();
    match run(Cli::parse().command) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("translucid: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(command: Command) -> translucid::Result<ExitCode> {
    let done = |result: translucid::Result<()>| result.map(|()| ExitCode::SUCCESS);
    match command {
        Command::Info => done(commands::info::run()),
        Command::Render {
            scene,
            method,
            threshold,
            wavelet,
            size,
            output,
            warm,
        } => done(commands::render::run(
            &scene, &method, threshold, wavelet, size, &output, warm,
        )),
        Command::Compare {
            scene,
            method,
            threshold,
            wavelet,
            size,
            output,
            json,
        } => commands::compare::run(
            &scene,
            &method,
            threshold,
            wavelet,
            size,
            output.as_deref(),
            json,
        ),
        Command::Conformance {
            paths,
            method,
            threshold,
            wavelet,
            size,
            json,
        } => commands::conformance::run(&paths, &method, threshold, wavelet, size, json),
        Command::Bench {
            scenes,
            methods,
            threshold,
            wavelet,
            size,
            frames,
            motion,
            json,
        } => done(commands::bench::run(
            &scenes,
            &methods,
            threshold,
            wavelet,
            commands::bench::FrameLoop {
                size,
                frames,
                motion,
            },
            json,
        )),
    }
}
