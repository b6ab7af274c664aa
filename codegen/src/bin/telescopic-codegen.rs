//! `telescopic-codegen MODELS.toml OUT_DIR`: generates every configuration of a models file
//! into `OUT_DIR/<key>.rs` (what `generated/build.rs` does, as a command). Prints the keys on
//! stderr; stdout stays empty (Symbolica's banner included).

use std::path::PathBuf;
use std::process::ExitCode;
use telescopic_codegen::{ModelList, generate};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [models, out] = args.as_slice() else {
        eprintln!("usage: telescopic-codegen MODELS.toml OUT_DIR");
        return ExitCode::from(2);
    };
    let run = || -> Result<(), String> {
        let text =
            std::fs::read_to_string(models).map_err(|e| format!("cannot read {models}: {e}"))?;
        let list: ModelList = toml::from_str(&text).map_err(|e| format!("{models}: {e}"))?;
        let out = PathBuf::from(out);
        std::fs::create_dir_all(&out)
            .map_err(|e| format!("cannot create {}: {e}", out.display()))?;
        for config in &list.model {
            let start = std::time::Instant::now();
            let model = generate(config).map_err(|e| format!("{}: {e}", config.key()))?;
            let path = out.join(format!("{}.rs", model.module));
            std::fs::write(&path, &model.source)
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
            eprintln!("{} ({:.3} s)", model.module, start.elapsed().as_secs_f64());
        }
        Ok(())
    };
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
