//! `telescopic fmu`: the scene's nonlinear model as an FMI 2.0 FMU.

use super::{SceneArgs, check_output};
use clap::Args;
use std::path::PathBuf;
use telescopic::fmu::{FmuKind, FmuVariables, MODEL_IDENTIFIER, write_fmu};

/// Options of `telescopic fmu`.
#[derive(Debug, Args)]
pub struct FmuArgs {
    #[command(flatten)]
    pub scene: SceneArgs,
    /// The FMU file to write (a zip; whole or not at all).
    #[arg(long, value_name = "FILE.fmu")]
    pub out: PathBuf,
    /// Interfaces: cs (co-simulation), me (model exchange) or both.
    #[arg(long, default_value = "both", value_name = "KIND")]
    pub kind: FmuKind,
    /// The FMU's shared library (the `telescopic-fmu` crate's cdylib); default:
    /// $TELESCOPIC_FMU_LIBRARY, else libtelescopic_fmu.so beside this executable.
    #[arg(long, value_name = "FILE.so")]
    pub library: Option<PathBuf>,
}

/// The shared library to pack: `--library`, `$TELESCOPIC_FMU_LIBRARY`, or beside the binary.
fn library(args: &FmuArgs) -> anyhow::Result<PathBuf> {
    if let Some(p) = &args.library {
        return Ok(p.clone());
    }
    if let Some(p) = std::env::var_os("TELESCOPIC_FMU_LIBRARY") {
        return Ok(PathBuf::from(p));
    }
    let exe = std::env::current_exe()?;
    let beside = exe.with_file_name(format!("lib{MODEL_IDENTIFIER}.so"));
    // test binaries live one level down, in deps/
    let above = exe
        .parent()
        .and_then(|d| d.parent())
        .map(|d| d.join(format!("lib{MODEL_IDENTIFIER}.so")));
    Ok(if beside.exists() {
        beside
    } else {
        above.filter(|p| p.exists()).unwrap_or(beside)
    })
}

/// Runs `telescopic fmu`.
pub fn fmu(args: &FmuArgs) -> anyhow::Result<()> {
    if args.out.extension().and_then(|e| e.to_str()) != Some("fmu") {
        anyhow::bail!(
            "--out: {}: an FMU's file name ends in .fmu",
            args.out.display()
        );
    }
    check_output("--out", Some(&args.out), &[&args.scene.scene])?;
    let scene = args.scene.load()?;
    let vars = FmuVariables::of(&scene)?;
    let library = library(args)?;
    write_fmu(&scene, &library, args.kind, &args.out)?;
    eprintln!(
        "{}: FMI 2.0 FMU ({}) with input {}, {} outputs, {} parameters, {} states, {} event \
         indicators; library {}\nwrote {}",
        scene.name,
        match args.kind {
            FmuKind::CoSimulation => "co-simulation",
            FmuKind::ModelExchange => "model exchange",
            FmuKind::Both => "co-simulation and model exchange",
        },
        vars.variables[0].name,
        vars.outputs,
        vars.parameters().count(),
        vars.states,
        vars.event_indicators,
        library.display(),
        args.out.display()
    );
    Ok(())
}
