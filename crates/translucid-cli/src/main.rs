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
    /// A folder whose files glTF buffer and image URIs may name, besides the glTF file's own
    /// folder (repeatable). Without it, a URI that leads out of the file's folder (an
    /// absolute path, `..`, a link) is refused: the files you render may not be yours.
    #[arg(long, global = true, value_name = "DIR")]
    allow_dir: Vec<PathBuf>,
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

/// How a scene named on the command line is drawn.
#[derive(clap::Args, Clone, Copy, Debug, Default)]
pub struct SceneArgs {
    /// Draw the scene's opaque surfaces as transparent ones of this alpha (in (0, 1]): any
    /// glTF becomes a load for the transparent methods
    #[arg(long, value_name = "A", value_parser = blend_alpha)]
    pub blend_alpha: Option<f32>,
}

fn blend_alpha(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(a) if a > 0.0 && a <= 1.0 => Ok(a),
        _ => Err(format!("{text:?} is not an alpha in (0, 1]")),
    }
}

/// What a bench sweep varies: `triangles=10k,30k,100k` (sized scenes, `hairball:N`) or
/// `size=512,1024,2048` (square frames of that side).
#[derive(Clone, Debug)]
pub struct Sweep {
    pub over: SweepOver,
    pub points: Vec<u64>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SweepOver {
    Triangles,
    Size,
}

impl std::str::FromStr for Sweep {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let (over, list) = s
            .split_once('=')
            .ok_or_else(|| format!("sweep {s:?} is not triangles=N,N,... or size=N,N,..."))?;
        let over = match over {
            "triangles" => SweepOver::Triangles,
            "size" => SweepOver::Size,
            other => return Err(format!("sweep over {other:?}: triangles or size")),
        };
        let points = list
            .split(',')
            .map(|p| {
                translucid::scene::generated::parse_count(p)
                    .filter(|&n| n > 0)
                    .ok_or_else(|| format!("sweep point {p:?} is not a count (10k, 1m, 512)"))
            })
            .collect::<Result<Vec<_>, _>>()?;
        if points.len() < 2 {
            return Err(format!("sweep {s:?}: at least two points, for a slope"));
        }
        Ok(Self { over, points })
    }
}

/// Settings of the methods that have any (other methods ignore them).
#[derive(clap::Args, Clone, Copy, Debug)]
pub struct MethodArgs {
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
    /// or full-screen images [default: the device's: bins on CPU drivers, images on GPUs;
    /// `translucid info` shows it]
    #[arg(long, value_enum)]
    pub storage: Option<Storage>,
    /// depth_peeling: peeling passes, fixed (each peels two layers; pixels with more are
    /// counted) [default: as many as the frame needs]
    #[arg(long)]
    pub passes: Option<u32>,
    /// exact, wavelet: draw with the shaders of a loop declared to draw this content, as
    /// `translucid_context_prepare` declares it, frames past it with the superset variant
    /// (comma-separated: textures, vertex-colours, corner-colours, lit, transmission,
    /// near-plane, deep, all, none) [default: no declaration, each frame's own]
    #[arg(long, value_parser = parse_declared)]
    pub declare: Option<translucid::methods::bins::features::DeclaredContent>,
}

/// `--declare`'s list.
fn parse_declared(
    list: &str,
) -> Result<translucid::methods::bins::features::DeclaredContent, String> {
    use translucid::methods::bins::features::DeclaredContent;
    let mut declared = DeclaredContent::default();
    for name in list.split(',').map(str::trim).filter(|n| !n.is_empty()) {
        match name {
            "textures" => declared.textures = true,
            "vertex-colours" => declared.vertex_colours = true,
            "corner-colours" => declared.corner_colours = true,
            "lit" => declared.lit = true,
            "transmission" => declared.transmission = true,
            "near-plane" => declared.near_plane = true,
            "deep" => declared.deep = true,
            "all" => declared = DeclaredContent::ALL,
            "none" => {}
            other => {
                return Err(format!(
                    "unknown content {other:?}: textures, vertex-colours, corner-colours, lit, \
                     transmission, near-plane, deep, all or none"
                ))
            }
        }
    }
    Ok(declared)
}

/// What changes between a bench's frames.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq, Hash)]
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

/// The most frames `bench` times per scene and method: more never changes a median, and
/// the frame counter must not wrap.
const MAX_BENCH_FRAMES: i64 = 100_000;

#[derive(Subcommand)]
enum Command {
    /// List Vulkan devices with the limits translucid sizes itself by.
    Info,
    /// Render a scene with one method and write a PNG.
    Render {
        /// A glTF path or a generated scene's name (boxes, spheres, particles, planes, ...).
        scene: String,
        /// blend, exact, wavelet, wboit, linked_list or depth_peeling
        #[arg(long, short, default_value = "exact")]
        method: String,
        /// exact: stop a pixel once its transmittance is under T in every channel (0: exact).
        #[arg(long, default_value_t = 0.0)]
        threshold: f32,
        #[command(flatten)]
        method_args: MethodArgs,
        #[arg(long, default_value = "1280x720")]
        size: Size,
        #[arg(short, long, default_value = "out/render.png")]
        output: PathBuf,
        /// Render the frame a second time and print that warm frame's stage times: the
        /// first frame's include building pipelines and compiling shaders.
        #[arg(long)]
        warm: bool,
        #[command(flatten)]
        scene_args: SceneArgs,
    },
    /// Render with a method and with the CPU reference, and measure the difference.
    Compare {
        scene: String,
        /// blend, exact, wavelet, wboit, linked_list or depth_peeling
        #[arg(long, short, default_value = "exact")]
        method: String,
        /// exact: stop a pixel once its transmittance is under T in every channel (0: exact).
        #[arg(long, default_value_t = 0.0)]
        threshold: f32,
        #[command(flatten)]
        method_args: MethodArgs,
        #[arg(long, default_value = "640x360")]
        size: Size,
        /// Write method | reference | error heat map side by side.
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        scene_args: SceneArgs,
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
        /// blend, exact, wavelet, wboit, linked_list or depth_peeling (blend's image errors never fail the run)
        #[arg(long, short, default_value = "exact")]
        method: String,
        /// exact: stop a pixel once its transmittance is under T in every channel (0: exact);
        /// checked against the reference with the same early stop.
        #[arg(long, default_value_t = 0.0)]
        threshold: f32,
        #[command(flatten)]
        method_args: MethodArgs,
        #[arg(long, default_value = "480x270")]
        size: Size,
        /// Print one JSON document instead of text.
        #[arg(long)]
        json: bool,
    },
    /// An engine's frame loop per method: the median GPU time of its whole pass over
    /// `native_blend`'s (an engine's own unsorted blend) and of each stage, from one run.
    Bench {
        #[arg(required = true)]
        scenes: Vec<String>,
        #[arg(long = "method", short, default_value = "exact")]
        methods: Vec<String>,
        /// exact: stop a pixel once its transmittance is under T in every channel (0: exact).
        #[arg(long, default_value_t = 0.0)]
        threshold: f32,
        #[command(flatten)]
        method_args: MethodArgs,
        #[arg(long, default_value = "1280x720")]
        size: Size,
        /// Timed frames per scene and method (1 to 100000), after two warm-up frames.
        #[arg(long, default_value_t = 20, value_parser = clap::value_parser!(u32).range(1..=MAX_BENCH_FRAMES))]
        frames: u32,
        /// What changes from frame to frame, as in an engine's frame loop; `orbit,static`
        /// runs both, taking turns, and reports moving over static from the same run.
        #[arg(long, value_enum, value_delimiter = ',', default_value = "orbit")]
        motion: Vec<Motion>,
        /// Print one JSON object per (scene, method) line instead of a table.
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        scene_args: SceneArgs,
        /// How the methods' cost grows: `triangles=10k,30k,100k,300k,1m` (scenes hairball or
        /// particles, cut into that many triangles) or `size=512,1024,2048,4096` (square
        /// frames). Prints each method's GPU ms per point and the log-log slope over
        /// triangles or pixels, and writes a plot (--plot)
        #[arg(long)]
        sweep: Option<Sweep>,
        /// Where a sweep's plot goes (SVG)
        #[arg(long, default_value = "out/sweep.svg")]
        plot: PathBuf,
    },
}

fn main() -> ExitCode {
    // The library's warnings (parts of a file it skips or cannot draw as written) on stderr;
    // RUST_LOG sets another level.
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn"))
        .format_timestamp(None)
        .init();
    let cli = Cli::parse();
    commands::set_import_options(translucid::scene::gltf::ImportOptions::allowing(
        cli.allow_dir,
    ));
    match run(cli.command) {
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
            method_args,
            size,
            output,
            warm,
            scene_args,
        } => done(commands::render::run(
            (&scene, scene_args),
            &method,
            threshold,
            method_args,
            size,
            &output,
            warm,
        )),
        Command::Compare {
            scene,
            method,
            threshold,
            method_args,
            size,
            output,
            json,
            scene_args,
        } => commands::compare::run(
            (&scene, scene_args),
            &method,
            threshold,
            method_args,
            size,
            output.as_deref(),
            json,
        ),
        Command::Conformance {
            paths,
            method,
            threshold,
            method_args,
            size,
            json,
        } => commands::conformance::run(&paths, &method, threshold, method_args, size, json),
        Command::Bench {
            scenes,
            methods,
            threshold,
            method_args,
            size,
            frames,
            motion,
            json,
            scene_args,
            sweep,
            plot,
        } => {
            let bench = commands::bench::Bench {
                methods: &methods,
                threshold,
                method_args,
                scene_args,
                frame_loop: commands::bench::FrameLoop {
                    size,
                    frames,
                    motion,
                },
            };
            match sweep {
                Some(sweep) => commands::sweep::run(&scenes, &bench, &sweep, &plot, json),
                None => done(commands::bench::run(&scenes, &bench, json)),
            }
        }
    }
}
