//! [`Builder`]: generation from a crate's own `build.rs` (in the style of prost-build and
//! bindgen), or into a directory meant to be committed, and the check that such a directory
//! is still what the generator makes.
//!
//! The files: one module `<key>.rs` per configuration (with `<key>.txt`, `<key>.tex` and
//! `<key>.json` renderings of its equations when asked), and `telescopic_models.rs`, which
//! declares a module per configuration (named by its key) and a lookup by key. Its
//! `include!`s are relative, so the same files work from `OUT_DIR` and from a committed
//! directory.

use crate::{CodegenError, GENERATOR_VERSION, ModelConfig, ModelList, generate};
use proc_macro2::TokenStream;
use quote::{format_ident, quote};
use std::fmt;
use std::path::{Path, PathBuf};

/// Name of the file that declares every generated module and the lookup by key.
pub const MODELS_FILE: &str = "telescopic_models.rs";

/// Extensions of the equation renderings written beside each module, with the format name
/// the lookup `rendering(key, format)` takes.
const RENDERINGS: [(&str, &str); 3] = [("text", "txt"), ("latex", "tex"), ("json", "json")];

/// Where a configuration came from, for error messages.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Origin {
    /// The `n`-th call of [`Builder::model`] (1-based).
    Call(usize),
    /// The `entry`-th `[[model]]` table (1-based) of a models file.
    File {
        /// The models file.
        path: PathBuf,
        /// 1-based position of the `[[model]]` table in it.
        entry: usize,
    },
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Origin::Call(n) => write!(f, "Builder::model call {n}"),
            Origin::File { path, entry } => {
                write!(f, "{}, [[model]] entry {entry}", path.display())
            }
        }
    }
}

impl std::fmt::Debug for BuildError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        std::fmt::Display::fmt(self, f)
    }
}

/// Why a [`Builder`] failed. Every message names the configuration (its key and where it was
/// given) or the file concerned. Its `Debug` form is the message too, so that a `build.rs`
/// whose `main` returns `Result<(), BuildError>` shows the message, not the variant.
#[derive(thiserror::Error)]
pub enum BuildError {
    /// Neither [`Builder::model`] nor [`Builder::models_file`] gave a configuration.
    #[error("no configurations to generate: call Builder::model or Builder::models_file")]
    Empty,
    /// A models file could not be read.
    #[error("cannot read the models file {path}: {error}")]
    Read {
        /// The file.
        path: PathBuf,
        /// The cause.
        error: std::io::Error,
    },
    /// A models file is not valid TOML or does not fit the schema.
    #[error("models file {path}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// The parser's message, with line, column and field.
        message: String,
    },
    /// A configuration breaks a rule.
    #[error("configuration {key} ({origin}): {rule}")]
    Invalid {
        /// The configuration's key.
        key: String,
        /// Where it was given.
        origin: Origin,
        /// The broken rule.
        rule: String,
    },
    /// Deriving or emitting a configuration failed.
    #[error("configuration {key} ({origin}): {error}")]
    Generate {
        /// The configuration's key.
        key: String,
        /// Where it was given.
        origin: Origin,
        /// What failed.
        error: CodegenError,
    },
    /// [`Builder::compile`] without [`Builder::out_dir`] outside a build script.
    #[error(
        "no output directory: call Builder::out_dir, or run inside a build script (OUT_DIR is \
         not set)"
    )]
    NoOutDir,
    /// The Symbolica lock file cannot be the one asked for.
    #[error("{0}")]
    Lock(String),
    /// A file could not be written, or a directory read.
    #[error("cannot write {path}: {error}")]
    Write {
        /// The file or directory.
        path: PathBuf,
        /// The cause.
        error: std::io::Error,
    },
    /// [`Builder::verify`]: the directory is not what a fresh generation gives.
    #[error(
        "{dir} is not what the generator makes now:\n{}\nRegenerate it (e.g. `cargo run -p \
         telescopic-codegen -- write MODELS.toml {dir}`) and review the diff.",
        .differences.iter().map(|d| format!("  - {d}")).collect::<Vec<_>>().join("\n")
    )]
    Stale {
        /// The directory checked.
        dir: String,
        /// One line per missing, changed or extra file.
        differences: Vec<String>,
    },
}

/// One file the generator makes: its name (no directory) and content.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GeneratedFile {
    /// File name, e.g. `s2_m5x5_c3_cable_linear_fixed_force.rs`.
    pub name: String,
    /// Content.
    pub content: String,
}

/// What [`Builder::compile`] or [`Builder::write_to`] did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Written {
    /// Keys of the generated configurations, sorted.
    pub keys: Vec<String>,
    /// Files whose content changed (or that were new), in the order written.
    pub changed: Vec<PathBuf>,
    /// Files left alone because their content was already right.
    pub unchanged: usize,
    /// Files of configurations no longer listed that were removed ([`Builder::write_to`]).
    pub removed: Vec<PathBuf>,
}

/// Generates models for a crate: from its `build.rs` into `OUT_DIR` ([`Builder::compile`]),
/// into a directory to commit ([`Builder::write_to`]), or checks such a directory
/// ([`Builder::verify`]).
///
/// In `build.rs` (the crate depends on `telescopic-runtime`, and on `telescopic-codegen` as a
/// build dependency):
///
/// ```no_run
/// use telescopic_codegen::{Builder, DriveKind, ForceFlow, ModelConfig, Positions};
///
/// fn main() -> Result<(), telescopic_codegen::BuildError> {
///     Builder::new()
///         .model(ModelConfig {
///             modes: vec![3, 3, 3],
///             contacts: 2,
///             force_flow: ForceFlow::External,
///             clearance: true,
///             positions: Positions::Fixed,
///             drive: DriveKind::Force,
///             static_knots: None,
///         })
///         .compile()?;
///     Ok(())
/// }
/// ```
///
/// and in the crate:
///
/// ```text
/// include!(concat!(env!("OUT_DIR"), "/telescopic_models.rs"));
/// // a module per configuration, e.g. s3_m3x3x3_c2_external_clearance_fixed_force, whose
/// // GeneratedModel implements telescopic_runtime::Model; CONFIGURATIONS; prepare(params);
/// // prepare_by_key(key, params); rendering(key, format)
/// ```
#[derive(Debug, Clone)]
pub struct Builder {
    models: Vec<ModelConfig>,
    models_files: Vec<PathBuf>,
    out_dir: Option<PathBuf>,
    renderings: bool,
    symbolica_lock: Option<PathBuf>,
}

impl Default for Builder {
    fn default() -> Self {
        Self::new()
    }
}

impl Builder {
    /// A builder with no configurations, output to `OUT_DIR`, renderings on.
    pub fn new() -> Self {
        Builder {
            models: Vec::new(),
            models_files: Vec::new(),
            out_dir: None,
            renderings: true,
            symbolica_lock: None,
        }
    }

    /// Adds one configuration (repeatable; a configuration given twice is generated once).
    pub fn model(mut self, config: ModelConfig) -> Self {
        self.models.push(config);
        self
    }

    /// Adds every `[[model]]` of a models file (TOML, see [`ModelList`]); a relative path is
    /// taken from the current directory, which is the crate's root in a build script.
    pub fn models_file(mut self, path: impl AsRef<Path>) -> Self {
        self.models_files.push(path.as_ref().to_owned());
        self
    }

    /// Where [`Builder::compile`] writes (default: `OUT_DIR`).
    pub fn out_dir(mut self, dir: impl AsRef<Path>) -> Self {
        self.out_dir = Some(dir.as_ref().to_owned());
        self
    }

    /// The lock file that serializes Symbolica across processes (default: see
    /// [`crate::lock_path`]); every cooperating process must name the same one. One process
    /// takes one lock: a later builder naming another fails.
    pub fn symbolica_lock(mut self, path: impl AsRef<Path>) -> Self {
        self.symbolica_lock = Some(path.as_ref().to_owned());
        self
    }

    /// Whether to write the text, LaTeX and JSON renderings of the equations beside each
    /// module (default: true); the lookup `rendering(key, format)` serves them.
    pub fn renderings(mut self, on: bool) -> Self {
        self.renderings = on;
        self
    }

    /// Every configuration with its origin: the `model` calls, then each models file in
    /// order; sorted by key, each key once.
    ///
    /// # Errors
    /// [`BuildError`] for an unreadable or malformed models file or an invalid
    /// configuration.
    pub fn configurations(&self) -> Result<Vec<(ModelConfig, Origin)>, BuildError> {
        let mut all: Vec<(ModelConfig, Origin)> = self
            .models
            .iter()
            .enumerate()
            .map(|(i, c)| (c.clone(), Origin::Call(i + 1)))
            .collect();
        for path in &self.models_files {
            let text = std::fs::read_to_string(path).map_err(|error| BuildError::Read {
                path: path.clone(),
                error,
            })?;
            let list: ModelList = toml::from_str(&text).map_err(|e| BuildError::Parse {
                path: path.clone(),
                message: e.to_string(),
            })?;
            all.extend(list.model.into_iter().enumerate().map(|(i, c)| {
                (
                    c,
                    Origin::File {
                        path: path.clone(),
                        entry: i + 1,
                    },
                )
            }));
        }
        if all.is_empty() {
            return Err(BuildError::Empty);
        }
        for (config, origin) in &all {
            config.validate().map_err(|rule| BuildError::Invalid {
                key: config.key(),
                origin: origin.clone(),
                rule,
            })?;
        }
        // the first origin of a repeated configuration is the one named in errors
        all.sort_by_key(|a| a.0.key());
        all.dedup_by(|later, first| later.0 == first.0);
        Ok(all)
    }

    /// Every file, in memory: the modules, their renderings and `telescopic_models.rs`.
    /// Touches no file but the models files it reads; runs Symbolica (one thread, behind
    /// the lock file: see `lock_path`).
    ///
    /// # Errors
    /// [`BuildError`] naming the configuration and the rule or the failed step.
    pub fn generate(&self) -> Result<Vec<GeneratedFile>, BuildError> {
        let configs = self.configurations()?;
        if let Some(path) = &self.symbolica_lock {
            crate::symbolic::use_lock_file(path).map_err(BuildError::Lock)?;
        }
        let mut files = Vec::new();
        let mut keys = Vec::new();
        for (config, origin) in &configs {
            let model = generate(config).map_err(|error| BuildError::Generate {
                key: config.key(),
                origin: origin.clone(),
                error,
            })?;
            files.push(GeneratedFile {
                name: format!("{}.rs", model.module),
                content: model.source,
            });
            if self.renderings {
                for (text, ext) in [
                    (model.text, "txt"),
                    (model.latex, "tex"),
                    (model.json, "json"),
                ] {
                    files.push(GeneratedFile {
                        name: format!("{}.{ext}", model.module),
                        content: text,
                    });
                }
            }
            keys.push((model.module, config.to_string()));
        }
        files.push(GeneratedFile {
            name: MODELS_FILE.to_string(),
            content: models_module(&keys, self.renderings),
        });
        Ok(files)
    }

    /// Generates into the output directory (default `OUT_DIR`), rewriting only files whose
    /// content changed, and prints `cargo:rerun-if-changed` for `build.rs` and each models
    /// file, so the script reruns only when they change. For `build.rs`.
    ///
    /// # Errors
    /// [`BuildError`]; [`BuildError::NoOutDir`] without `out_dir` outside a build script.
    pub fn compile(&self) -> Result<Written, BuildError> {
        // the configurations given with `model` live in build.rs: without this line cargo
        // would rerun the script (and Symbolica) after any change to the package
        println!("cargo:rerun-if-changed=build.rs");
        let dir = match &self.out_dir {
            Some(d) => d.clone(),
            None => std::env::var_os("OUT_DIR")
                .map(PathBuf::from)
                .ok_or(BuildError::NoOutDir)?,
        };
        for path in &self.models_files {
            println!("cargo:rerun-if-changed={}", path.display());
        }
        self.write(&dir)
    }

    /// Generates into `dir` for committing, so that the crate builds without running
    /// Symbolica: rewrites only changed files and removes the files of configurations no
    /// longer listed. Prints nothing.
    ///
    /// # Errors
    /// [`BuildError`].
    pub fn write_to(&self, dir: impl AsRef<Path>) -> Result<Written, BuildError> {
        self.write(dir.as_ref())
    }

    /// Checks that `dir` holds exactly what [`Builder::write_to`] would write: no file
    /// missing, changed or left over from an earlier configuration.
    ///
    /// # Errors
    /// [`BuildError::Stale`] listing every difference, or a generation error.
    pub fn verify(&self, dir: impl AsRef<Path>) -> Result<(), BuildError> {
        let dir = dir.as_ref();
        let files = self.generate()?;
        let mut differences = Vec::new();
        for f in &files {
            match std::fs::read_to_string(dir.join(&f.name)) {
                Err(_) => differences.push(format!("{}: missing", f.name)),
                Ok(old) if old != f.content => {
                    let line = first_difference(&old, &f.content);
                    differences.push(format!("{}: differs from line {line} on", f.name));
                }
                Ok(_) => {}
            }
        }
        for name in leftover_files(dir, &files)? {
            differences.push(format!(
                "{name}: left over (its configuration is no longer listed)"
            ));
        }
        if differences.is_empty() {
            Ok(())
        } else {
            Err(BuildError::Stale {
                dir: dir.display().to_string(),
                differences,
            })
        }
    }

    fn write(&self, dir: &Path) -> Result<Written, BuildError> {
        let files = self.generate()?;
        let write_error = |path: &Path, error| BuildError::Write {
            path: path.to_owned(),
            error,
        };
        std::fs::create_dir_all(dir).map_err(|e| write_error(dir, e))?;
        let mut written = Written {
            keys: Vec::new(),
            changed: Vec::new(),
            unchanged: 0,
            removed: Vec::new(),
        };
        for name in leftover_files(dir, &files)? {
            let path = dir.join(name);
            std::fs::remove_file(&path).map_err(|e| write_error(&path, e))?;
            written.removed.push(path);
        }
        for f in &files {
            let path = dir.join(&f.name);
            if f.name.ends_with(".rs") && f.name != MODELS_FILE {
                written
                    .keys
                    .push(f.name.trim_end_matches(".rs").to_string());
            }
            if std::fs::read_to_string(&path).ok().as_deref() == Some(f.content.as_str()) {
                written.unchanged += 1;
                continue;
            }
            std::fs::write(&path, &f.content).map_err(|e| write_error(&path, e))?;
            written.changed.push(path);
        }
        Ok(written)
    }
}

/// 1-based number of the first line where `a` and `b` differ.
fn first_difference(a: &str, b: &str) -> usize {
    let mut lines = a.lines().zip(b.lines());
    lines
        .position(|(x, y)| x != y)
        .unwrap_or_else(|| a.lines().count().min(b.lines().count()))
        + 1
}

/// Files in `dir` that an earlier generation wrote (listed by its `telescopic_models.rs`)
/// and that `files` no longer contain.
fn leftover_files(dir: &Path, files: &[GeneratedFile]) -> Result<Vec<String>, BuildError> {
    let Ok(old) = std::fs::read_to_string(dir.join(MODELS_FILE)) else {
        return Ok(Vec::new());
    };
    let mut leftover = Vec::new();
    for key in included_keys(&old) {
        for ext in ["rs", "txt", "tex", "json"] {
            let name = format!("{key}.{ext}");
            if dir.join(&name).exists() && !files.iter().any(|f| f.name == name) {
                leftover.push(name);
            }
        }
    }
    Ok(leftover)
}

/// The module keys an existing `telescopic_models.rs` includes.
fn included_keys(models_rs: &str) -> Vec<String> {
    models_rs
        .split("include!(\"")
        .skip(1)
        .filter_map(|rest| rest.split_once(".rs\")").map(|(k, _)| k.to_string()))
        .filter(|k| !k.contains(['/', '\\', '"']))
        .collect()
}

/// `telescopic_models.rs`: a module per configuration, `CONFIGURATIONS`, `prepare_by_key`,
/// `prepare` and `rendering`. `keys`: (key, configuration as text), sorted.
fn models_module(keys: &[(String, String)], renderings: bool) -> String {
    let modules = keys.iter().map(|(key, description)| {
        let ident = format_ident!("{}", key);
        let file = format!("{key}.rs");
        let doc = format!(" Generated model for configuration `{key}`: {description}.");
        quote! {
            #[doc = #doc]
            #[allow(clippy::all, dead_code, unused_variables, non_snake_case, missing_docs)]
            pub mod #ident { include!(#file); }
        }
    });
    let names = keys.iter().map(|(k, _)| k.as_str());
    let arms = keys.iter().map(|(key, _)| {
        let ident = format_ident!("{}", key);
        quote! {
            #key => Some(#ident::GeneratedModel::prepare(params)
                .map(|m| Box::new(m) as Box<dyn telescopic_runtime::Model>)),
        }
    });
    let rendering_arms = keys.iter().flat_map(|(key, _)| {
        let mut arms: Vec<TokenStream> = Vec::new();
        let rust = format!("{key}.rs");
        arms.push(quote!( (#key, "rust") => Some(include_str!(#rust)), ));
        if renderings {
            for (format, ext) in RENDERINGS {
                let file = format!("{key}.{ext}");
                arms.push(quote!( (#key, #format) => Some(include_str!(#file)), ));
            }
        }
        arms
    });
    let formats = if renderings {
        "`text`, `latex`, `json` or `rust` (the emitted module itself)"
    } else {
        "`rust` (the emitted module itself; renderings were not generated)"
    };
    let rendering_doc = format!(
        " The equations of model `key` as generated: `format` is {formats}; `None` for an \
         unknown key or format."
    );
    let file = quote! {
        /// Keys of every generated configuration, sorted.
        pub const CONFIGURATIONS: &[&str] = &[#(#names),*];

        /// Prepares the generated model `key` for `params`; `None` if no such model was
        /// generated, `Some(Err)` if the parameters do not fit it.
        pub fn prepare_by_key(
            key: &str,
            params: &telescopic_runtime::ModelParams,
        ) -> Option<Result<Box<dyn telescopic_runtime::Model>, String>> {
            match key {
                #(#arms)*
                _ => None,
            }
        }

        /// The generated model for `params` (found by its configuration key), if that
        /// configuration was generated.
        pub fn prepare(
            params: &telescopic_runtime::ModelParams,
        ) -> Option<Result<Box<dyn telescopic_runtime::Model>, String>> {
            prepare_by_key(&telescopic_runtime::configuration_key(params), params)
        }

        #[doc = #rendering_doc]
        pub fn rendering(key: &str, format: &str) -> Option<&'static str> {
            match (key, format) {
                #(#rendering_arms)*
                _ => None,
            }
        }
    };
    let modules = quote!(#(#modules)*);
    let body = prettyplease::unparse(
        &syn::parse2(quote!(#modules #file)).expect("the models module is valid Rust"),
    );
    let list: Vec<&str> = keys.iter().map(|(k, _)| k.as_str()).collect();
    format!(
        "// @generated by telescopic-codegen {GENERATOR_VERSION}; do not edit.\n\
         // Every generated configuration: {}.\n\
         // Include it with include!(concat!(env!(\"OUT_DIR\"), \"/{MODELS_FILE}\")), or by the\n\
         // path of a committed copy; it needs the crate telescopic-runtime.\n\n{body}",
        list.join(", ")
    )
}
