//! `modelDescription.xml` of a scene's FMU (FMI 2.0): variables with units and
//! descriptions, the model structure, and a GUID that is a hash of the rest, so the FMU's
//! library can check that the description it was shipped with is the one its scene gives.
//! Hand-written: the XML is a few fixed elements around the variable list; no XML crate is
//! needed to write it.

use super::variables::{Causality, FmuVariables, Variable};
use crate::Result;
use sha2::{Digest, Sha256};
use std::fmt::Write as _;
use telescopic_runtime::Scene;

/// The model identifier: the shared library's name in the FMU (`binaries/linux64/<id>.so`)
/// and the prefix nothing else uses.
pub const MODEL_IDENTIFIER: &str = "telescopic_fmu";

/// Which interfaces the FMU offers.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FmuKind {
    /// Co-simulation: the FMU integrates with its own methods.
    CoSimulation,
    /// Model exchange: the importer integrates the states.
    ModelExchange,
    /// Both (the default).
    #[default]
    Both,
}

crate::named::named_enum!(FmuKind, "an FMU kind", {
    CoSimulation => "cs",
    ModelExchange => "me",
    Both => "both",
});

/// The units the variables use, with their SI base units (`kg`, `m`, `s` exponents).
const UNITS: [(&str, i32, i32, i32); 8] = [
    ("m", 0, 1, 0),
    ("N", 1, 1, -2),
    ("kg", 1, 0, 0),
    ("m/s2", 0, 1, -2),
    ("N/m", 1, 0, -2),
    ("N.s/m", 1, 0, -1),
    ("1/m", 0, -1, 0),
    ("1", 0, 0, 0),
];

/// Text with `&`, `<`, `>` and `"` escaped for an XML attribute.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The description of `scene`'s FMU offering `kind`.
///
/// # Errors
/// As [`FmuVariables::of`].
pub fn model_description(scene: &Scene, kind: FmuKind) -> Result<String> {
    let vars = FmuVariables::of(scene)?;
    let guid = guid(&description_body(scene, &vars, FmuKind::Both));
    Ok(description_body(scene, &vars, kind).replace("{GUID}", &guid))
}

/// The GUID of `scene`'s FMU: the hash of its description with both interfaces, whatever
/// the kind exported (the FMU's library recomputes it from the scene it carries).
///
/// # Errors
/// As [`FmuVariables::of`].
pub fn scene_guid(scene: &Scene) -> Result<String> {
    let vars = FmuVariables::of(scene)?;
    Ok(guid(&description_body(scene, &vars, FmuKind::Both)))
}

/// The GUID of a description written with the placeholder `{GUID}`: the SHA-256 of that text,
/// in the 8-4-4-4-12 form.
pub fn guid(body: &str) -> String {
    let hash = Sha256::digest(body.as_bytes());
    let hex: String = hash.iter().take(16).map(|b| format!("{b:02x}")).collect();
    format!(
        "{{{}-{}-{}-{}-{}}}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    )
}

/// The description with `{GUID}` in place of the GUID.
fn description_body(scene: &Scene, vars: &FmuVariables, kind: FmuKind) -> String {
    let mut s = String::from("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    let _ = writeln!(
        s,
        "<fmiModelDescription fmiVersion=\"2.0\" modelName=\"{}\" guid=\"{{GUID}}\" \
         description=\"{}\" generationTool=\"telescopic {}\" variableNamingConvention=\"flat\" \
         numberOfEventIndicators=\"{}\">",
        escape(&scene.name),
        escape(&scene.description),
        env!("CARGO_PKG_VERSION"),
        vars.event_indicators
    );
    if kind != FmuKind::CoSimulation {
        let _ = writeln!(
            s,
            "  <ModelExchange modelIdentifier=\"{MODEL_IDENTIFIER}\" \
             completedIntegratorStepNotNeeded=\"true\"/>"
        );
    }
    if kind != FmuKind::ModelExchange {
        let _ = writeln!(
            s,
            "  <CoSimulation modelIdentifier=\"{MODEL_IDENTIFIER}\" \
             canHandleVariableCommunicationStepSize=\"true\"/>"
        );
    }
    s.push_str("  <UnitDefinitions>\n");
    for (name, kg, m, sec) in UNITS {
        let mut base = String::new();
        for (unit, e) in [("kg", kg), ("m", m), ("s", sec)] {
            if e != 0 {
                let _ = write!(base, " {unit}=\"{e}\"");
            }
        }
        let _ = writeln!(s, "    <Unit name=\"{name}\"><BaseUnit{base}/></Unit>");
    }
    s.push_str("  </UnitDefinitions>\n");
    let t = &scene.time;
    let _ = writeln!(
        s,
        "  <DefaultExperiment startTime=\"{}\" stopTime=\"{}\" stepSize=\"{}\"/>",
        t.start, t.end, t.sample
    );
    s.push_str("  <ModelVariables>\n");
    for v in &vars.variables {
        s.push_str(&scalar_variable(v));
    }
    s.push_str("  </ModelVariables>\n  <ModelStructure>\n    <Outputs>\n");
    let index = |v: &Variable| v.reference as usize + 1;
    let outputs: Vec<&Variable> = vars
        .variables
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .collect();
    let derivatives: Vec<&Variable> = vars
        .variables
        .iter()
        .filter(|v| v.derivative_of.is_some())
        .collect();
    for v in &outputs {
        let _ = writeln!(s, "      <Unknown index=\"{}\"/>", index(v));
    }
    s.push_str("    </Outputs>\n    <Derivatives>\n");
    for v in &derivatives {
        let _ = writeln!(s, "      <Unknown index=\"{}\"/>", index(v));
    }
    s.push_str("    </Derivatives>\n    <InitialUnknowns>\n");
    for v in outputs.iter().chain(&derivatives) {
        let _ = writeln!(s, "      <Unknown index=\"{}\"/>", index(v));
    }
    s.push_str("    </InitialUnknowns>\n  </ModelStructure>\n</fmiModelDescription>\n");
    s
}

/// One `<ScalarVariable>` element.
fn scalar_variable(v: &Variable) -> String {
    let (causality, variability, initial) = match (v.causality, v.derivative_of) {
        (Causality::Input, _) => ("input", "continuous", ""),
        (Causality::Output, _) => ("output", "continuous", ""),
        (Causality::Parameter, _) => ("parameter", "fixed", " initial=\"exact\""),
        (Causality::Local, None) => ("local", "continuous", " initial=\"exact\""),
        (Causality::Local, Some(_)) => ("local", "continuous", ""),
    };
    let mut real = String::new();
    if !v.unit.is_empty() {
        let _ = write!(real, " unit=\"{}\"", escape(&v.unit));
    }
    if let Some(start) = v.start {
        let _ = write!(real, " start=\"{start:e}\"");
    }
    if let Some(state) = v.derivative_of {
        let _ = write!(real, " derivative=\"{state}\"");
    }
    format!(
        "    <ScalarVariable name=\"{}\" valueReference=\"{}\" description=\"{}\" \
         causality=\"{causality}\" variability=\"{variability}\"{initial}><Real{real}/></ScalarVariable>\n",
        escape(&v.name),
        v.reference,
        escape(&v.description)
    )
}
