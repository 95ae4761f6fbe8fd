//! # cardan-cli: the `cardan` command
//!
//! Model file (TOML, `docs/model-format.md`) → [`cardan_mechanism`] model → analysis → CSV files
//! and SVG plots. The binary (`src/main.rs`) only calls [`main_with_args`]; everything else lives
//! here so that tests can call it.
//!
//! - `cardan run MODEL.toml [-o DIR] [--quiet] [--strict] [--allow-long] [--png]`: the analysis the
//!   file describes; CSV per output group (header with units), SVG plots, `run.json`, a summary
//!   line with warnings ([`output`]: the directory rule; [`progress`]: progress bar and Ctrl-C).
//! - `cardan check MODEL.toml`: bodies, joints with equation counts, DOF, redundant equations.
//! - `cardan import MODEL.asmt [-o MODEL.toml]`: an ASMT file (OndselSolver / FreeCAD Assembly)
//!   as a cardan model; `run` and `check` also take `.asmt` files directly (`--units si|mm`,
//!   `--analysis kinematic|inverse_dynamics|dynamic`).
//! - `cardan eval MODEL.toml [--t T] [--format text|json|csv] [--set NAME=VALUE]`: Φ, the Jacobian (pattern and
//!   values), ν and γ# at the assembled state; JSON at full precision with row and column maps.
//!
//! Every failure is an [`Error`] with a one-paragraph message (file:line:column when it comes
//! from the model file) and an exit code; bad input never panics.

pub mod commands;
pub mod output;
pub mod progress;
pub mod watch;

pub use cardan_model::diag::{Error, ErrorKind, Location, Source};
use cardan_model::{asmt, check, eval, output_tables};

use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// The `cardan` command line.
#[derive(Debug, Parser)]
#[command(
    name = "cardan",
    version,
    about = "Kinematic, static, modal, inverse and forward dynamics analysis of spatial mechanisms \
             (absolute coordinates, Euler parameters), from TOML models or FreeCAD/OndselSolver \
             ASMT assemblies",
    long_about = None
)]
pub struct Cli {
    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run the analysis the model file describes; write CSV, plots and the report
    /// (index.html).
    Run {
        /// The model file (TOML).
        model: PathBuf,
        /// Output directory (default: out/NAME/, NAME the model's name).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Do not show a progress bar.
        #[arg(long)]
        quiet: bool,
        /// Treat warnings about doubtful results as failures: exit code 3 (the results are
        /// still written; run.json says "complete" with the warnings).
        #[arg(long)]
        strict: bool,
        /// Run a dynamic analysis even if it needs more than 10 000 000 integration steps
        /// (Ctrl-C stops a run and keeps its results).
        #[arg(long)]
        allow_long: bool,
        /// Also write each plot as PNG (rendered from its SVG; text needs a system font).
        #[arg(long)]
        png: bool,
        /// Which files to write besides run.json, comma-separated (default: all): csv (the
        /// tables), plots, report (animation.glb, index.html), asmt (an ASMT model's
        /// .solved.asmt). `--outputs asmt` is the fastest run of an ASMT file.
        #[arg(long, value_enum, value_delimiter = ',')]
        outputs: Vec<OutputKind>,
        /// How an ASMT model file is read.
        #[command(flatten)]
        asmt: AsmtArgs,
    },
    /// Validate the model; print bodies, joints, equation counts, DOF and redundant equations.
    Check {
        /// The model file (TOML).
        model: PathBuf,
        /// How an ASMT model file is read.
        #[command(flatten)]
        asmt: AsmtArgs,
    },
    /// Write the cardan model (TOML) equivalent to an ASMT file (OndselSolver / FreeCAD
    /// Assembly) or a URDF robot, with comments tracing each element to its source.
    Import {
        /// The ASMT or URDF file.
        model: PathBuf,
        /// The TOML file to write (default: standard output).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// The units of the file's numbers: SI (m, kg, s) or mm (FreeCAD exports; converted
        /// to SI).
        #[arg(long, value_enum, default_value_t = asmt::Units::Si)]
        units: asmt::Units,
        /// The analysis the model file asks for (default: the ASMT file's kinematics).
        #[arg(long, value_enum, default_value_t = asmt::Analysis::Kinematic)]
        analysis: asmt::Analysis,
        /// How a URDF file is read.
        #[command(flatten)]
        urdf: UrdfArgs,
    },
    /// Run the model for every case of a grid of parameter values (or of a cases file) on
    /// all cores; write sweep.csv (a row per case), a plot of each output against each
    /// parameter and run.json.
    Sweep {
        /// The model file (TOML, with a parameters table).
        model: PathBuf,
        /// An axis of the grid: NAME=A:B:N (N values from A to B; "60 mm:100 mm:5"),
        /// NAME=V1,V2,... or NAME=V. Repeatable: the grid is every combination.
        #[arg(long = "set", value_name = "NAME=VALUES", value_parser = parse_setting)]
        set: Vec<(String, String)>,
        /// The cases as a CSV file: the parameter names in the header, a case per row.
        #[arg(long)]
        cases: Option<PathBuf>,
        /// An output: NAME=EXPR over the run's tables, e.g.
        /// "peak_torque=max(abs(motor.torque))", "top=max(abs(slider.C.x'))" (' the velocity),
        /// "work=integral(motor.P)", "mid=at(crank_pin.angle, 0.5)". Repeatable.
        #[arg(long = "output", value_name = "NAME=EXPR")]
        outputs: Vec<String>,
        /// Output directory (default: out/STEM-sweep/, STEM the model file's name).
        #[arg(short = 'o', long = "out-dir")]
        dir: Option<PathBuf>,
        /// Threads (default: one per core).
        #[arg(short = 'j', long)]
        jobs: Option<usize>,
        /// Run more than 100 000 cases.
        #[arg(long)]
        allow_long: bool,
    },
    /// A live preview: serves the model's report on 127.0.0.1 and re-solves it whenever the
    /// file is saved or a parameter's slider moves (Ctrl-C ends it).
    Watch {
        /// The model file (TOML).
        model: PathBuf,
        /// The port (default 0: a free one, printed).
        #[arg(long, default_value_t = 0)]
        port: u16,
    },
    /// Print Φ, the Jacobian (pattern and values), ν and γ# at the assembled state.
    Eval {
        /// The model file (TOML).
        model: PathBuf,
        /// Time in seconds at which to assemble and evaluate (default: the analysis start time).
        #[arg(long = "t", allow_negative_numbers = true)]
        t: Option<f64>,
        /// Output format: tables to read, or JSON at full precision with the row and column maps.
        #[arg(long, value_enum, default_value_t = eval::Format::Text)]
        format: eval::Format,
        /// A value for one of the model's `[parameters]` (repeatable), as for `run`.
        #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_setting)]
        set: Vec<(String, String)>,
    },
}

/// One value of `cardan run --outputs`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum OutputKind {
    /// The tables as CSV files.
    Csv,
    /// The tables' plots.
    Plots,
    /// animation.glb and index.html.
    Report,
    /// An ASMT model's .solved.asmt.
    Asmt,
}

impl OutputKind {
    /// The set `--outputs` names (every output when it names none).
    pub fn set(kinds: &[OutputKind]) -> cardan_model::analysis::OutputSet {
        if kinds.is_empty() {
            return cardan_model::analysis::OutputSet::ALL;
        }
        let has = |k: OutputKind| kinds.contains(&k);
        cardan_model::analysis::OutputSet {
            csv: has(OutputKind::Csv),
            plots: has(OutputKind::Plots),
            report: has(OutputKind::Report),
            asmt: has(OutputKind::Asmt),
        }
    }
}

/// `--units` and `--analysis` of `run` and `check`: how an ASMT file is read (a TOML model
/// says both itself, and refuses them); `--set`: a cardan model's parameter values.
#[derive(Debug, Clone, clap::Args)]
pub struct AsmtArgs {
    /// A value for one of the model file's parameters, replacing its own: `--set crank=0.1`
    /// (a plain number is in the model's units of the parameter), `--set crank="90 mm"`,
    /// `--set speed="2 * pi"`. Repeatable.
    #[arg(long = "set", value_name = "NAME=VALUE", value_parser = parse_setting)]
    pub set: Vec<(String, String)>,
    /// ASMT files: the units of the file's numbers, SI (m, kg, s) or mm (FreeCAD exports).
    #[arg(long, value_enum)]
    pub units: Option<asmt::Units>,
    /// ASMT files: the analysis to run (default: the file's kinematics).
    #[arg(long, value_enum)]
    pub analysis: Option<asmt::Analysis>,
    /// How a URDF file is read.
    #[command(flatten)]
    pub urdf: UrdfArgs,
}

/// `--base`, `--mimic` and `--no-limits`: how a URDF file is read.
#[derive(Debug, Clone, Copy, clap::Args)]
pub struct UrdfArgs {
    /// URDF files: the root link fixed to the ground (default) or floating (a free-flyer
    /// base: a humanoid, a quadruped).
    #[arg(long, value_enum)]
    pub base: Option<UrdfBase>,
    /// URDF files: mimic joints as gear couplers (default) or as free joints (Pinocchio's
    /// default reading).
    #[arg(long, value_enum)]
    pub mimic: Option<UrdfMimic>,
    /// URDF files: no stops at the joints' position limits.
    #[arg(long)]
    pub no_limits: bool,
    /// URDF files: each revolute or prismatic joint's `<dynamics damping>` as a damper (torque
    /// or force −c q̇).
    #[arg(long)]
    pub damping: bool,
    /// URDF files: each revolute or prismatic joint's `<dynamics friction>` as a constant
    /// friction torque or force against the motion (`[[friction]] law = "constant"`).
    #[arg(long)]
    pub friction: bool,
}

/// `--base` of a URDF file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum UrdfBase {
    /// The root link is the ground.
    Fixed,
    /// The root link's body moves freely.
    Floating,
}

/// `--mimic` of a URDF file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum UrdfMimic {
    /// A gear coupler per mimic joint.
    Couple,
    /// Mimic joints move freely.
    Free,
}

impl UrdfArgs {
    /// Whether any URDF flag is given.
    fn given(&self) -> bool {
        self.base.is_some()
            || self.mimic.is_some()
            || self.no_limits
            || self.damping
            || self.friction
    }

    /// The URDF reading the flags ask for.
    fn options(&self) -> cardan_model::urdf::UrdfOptions {
        use cardan_model::urdf::{Base, MimicMode, UrdfOptions};
        UrdfOptions {
            base: match self.base {
                Some(UrdfBase::Floating) => Base::Floating,
                _ => Base::Fixed,
            },
            mimic: match self.mimic {
                Some(UrdfMimic::Free) => MimicMode::Free,
                _ => MimicMode::Couple,
            },
            limits: !self.no_limits,
            damping: self.damping,
            friction: self.friction,
            // Collision shapes come from an overlay's [urdf] only.
            self_collision: false,
        }
    }
}

/// `NAME=VALUE` of `--set`.
fn parse_setting(text: &str) -> Result<(String, String), String> {
    match text.split_once('=') {
        Some((name, value)) if !name.trim().is_empty() && !value.trim().is_empty() => {
            Ok((name.trim().to_string(), value.trim().to_string()))
        }
        _ => Err(format!(
            "\"{text}\" is not NAME=VALUE (e.g. --set crank=0.1 or --set crank=\"90 mm\")"
        )),
    }
}

impl AsmtArgs {
    /// The options, or an error for a model given a flag of another format.
    fn options(&self, model: &std::path::Path) -> Result<asmt::AsmtOptions, Error> {
        if !cardan_model::urdf::is_urdf(model) && self.urdf.given() {
            return Err(Error::usage(format!(
                "--base, --mimic and --no-limits apply to URDF files (.urdf); {} is not one",
                model.display()
            )));
        }
        if !asmt::is_asmt(model) && (self.units.is_some() || self.analysis.is_some()) {
            return Err(Error::usage(format!(
                "--units and --analysis apply to ASMT files (.asmt); {} is a cardan model, \
                 which gives its units in [model] units and its analysis in [analysis] kind",
                model.display()
            )));
        }
        Ok(asmt::AsmtOptions {
            set: self.set.clone(),
            urdf: self.urdf.options(),
            units: self.units.unwrap_or_default(),
            analysis: self.analysis.unwrap_or_default(),
        })
    }
}

/// Runs a parsed command line, writing reports to `out`.
///
/// # Errors
/// The one-paragraph [`Error`] to print.
pub fn run(cli: &Cli, out: &mut dyn std::io::Write) -> Result<(), Error> {
    match &cli.command {
        Command::Run {
            model,
            output,
            quiet,
            strict,
            allow_long,
            png,
            outputs,
            asmt,
        } => {
            let shown = !*quiet && std::io::IsTerminal::is_terminal(&std::io::stderr());
            let flags = cardan_model::analysis::RunFlags {
                progress: shown
                    .then_some(progress::terminal_bar as cardan_model::progress::MakeBar),
                strict: *strict,
                allow_long: *allow_long,
                png: *png,
                asmt: asmt.options(model)?,
                outputs: OutputKind::set(outputs),
            };
            commands::run::run(model, output.as_deref(), &flags, out).map(|_| ())
        }
        Command::Check { model, asmt } => {
            // A large model's report has three lines per body and joint: written through the
            // line-buffered standard output, one system call each (30,000 for 10,000 bodies).
            let mut buffered = std::io::BufWriter::new(out);
            let result = check::check_with(model, asmt.options(model)?, &mut buffered);
            let flushed = std::io::Write::flush(&mut buffered).map_err(output_tables::io);
            result.and(flushed)
        }
        Command::Import {
            model,
            output,
            units,
            analysis,
            urdf,
        } => {
            let options = asmt::AsmtOptions {
                units: *units,
                analysis: *analysis,
                urdf: urdf.options(),
                set: Vec::new(),
            };
            commands::asmt::import(model, output.as_deref(), options, out)
        }
        Command::Sweep {
            model,
            set,
            cases,
            outputs,
            dir,
            jobs,
            allow_long,
        } => commands::sweep::sweep(
            &commands::sweep::SweepArgs {
                model: model.clone(),
                set: set.clone(),
                cases: cases.clone(),
                outputs: outputs.clone(),
                dir: dir.clone(),
                jobs: *jobs,
                allow_long: *allow_long,
            },
            out,
        ),
        Command::Watch { model, port } => watch::watch(model, *port, out),
        Command::Eval {
            model,
            t,
            format,
            set,
        } => eval::eval_with(model, *t, set, *format, out),
    }
}

/// The whole program: parses `args`, runs, prints errors, returns the exit code.
pub fn main_with_args(args: impl IntoIterator<Item = std::ffi::OsString>) -> i32 {
    let cli = match Cli::try_parse_from(args) {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return code;
        }
    };
    let stdout = std::io::stdout();
    let mut lock = stdout.lock();
    match run(&cli, &mut lock) {
        Ok(()) => 0,
        Err(e) => {
            use std::io::Write as _;
            let _ = lock.flush();
            if e.kind != ErrorKind::BrokenPipe {
                eprintln!("{e}");
            }
            e.kind.exit_code()
        }
    }
}
