//! Property tests of the scene parser and the `--set` overrides: documents built from the
//! schema with random values (negative, zero, huge, tiny, NaN, infinite, wrong types,
//! missing and unknown keys), random overrides, and random bytes. Every input either loads
//! or is rejected with an error that names the field (or the line, or the argument); none
//! panics, and none allocates more than a bound (a counting allocator watches the peak).

use proptest::prelude::*;
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use telescopic_runtime::{Scene, SceneError};

/// The system allocator, counting the bytes live now and their peak.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let now = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(now, Ordering::Relaxed);
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Most bytes one load may hold at once beyond what was live before it.
const ALLOCATION_BOUND: usize = 64 << 20;

/// Top-level tables of a scene.
const TABLES: [&str; 8] = [
    "sections",
    "masses",
    "gravity",
    "contact",
    "telescope",
    "drive",
    "time",
    "reference",
];

/// A number from the edges of the physics and of `f64`.
fn number() -> impl Strategy<Value = toml::Value> + Clone {
    prop_oneof![
        4 => (0.001f64..3.0).prop_map(toml::Value::Float),
        1 => Just(toml::Value::Float(0.0)),
        1 => Just(toml::Value::Float(-1.0)),
        1 => Just(toml::Value::Float(1e300)),
        1 => Just(toml::Value::Float(1e-300)),
        1 => Just(toml::Value::Float(f64::NAN)),
        1 => Just(toml::Value::Float(f64::INFINITY)),
        1 => Just(toml::Value::Float(f64::NEG_INFINITY)),
        1 => any::<f64>().prop_map(toml::Value::Float),
        1 => any::<i64>().prop_map(toml::Value::Integer),
    ]
}

/// A count (sections, modes, contact points): small, zero, negative or huge.
fn count() -> impl Strategy<Value = toml::Value> + Clone {
    prop_oneof![
        4 => (1i64..6).prop_map(toml::Value::Integer),
        1 => Just(toml::Value::Integer(0)),
        1 => Just(toml::Value::Integer(-3)),
        1 => Just(toml::Value::Integer(i64::MAX)),
        1 => Just(toml::Value::Integer(1_000_000_000_000)),
        1 => (17i64..100).prop_map(toml::Value::Integer),
        1 => Just(toml::Value::Float(2.5)),
    ]
}

/// Any value of the wrong type for most fields.
fn wrong_type() -> impl Strategy<Value = toml::Value> + Clone {
    prop_oneof![
        Just(toml::Value::String("big".into())),
        Just(toml::Value::Boolean(true)),
        Just(toml::Value::Array(vec![])),
        Just(toml::Value::Table(toml::Table::new())),
    ]
}

/// A field's value: mostly of the right kind, sometimes a list, sometimes the wrong type.
fn value(
    numeric: impl Strategy<Value = toml::Value> + Clone,
) -> impl Strategy<Value = toml::Value> + Clone {
    prop_oneof![
        6 => numeric.clone(),
        2 => prop::collection::vec(numeric, 0..5).prop_map(toml::Value::Array),
        1 => wrong_type(),
    ]
}

/// A profile: a number or a table of one of the kinds, with random fields.
fn profile() -> impl Strategy<Value = toml::Value> + Clone {
    let list = || prop::collection::vec(number(), 0..5).prop_map(toml::Value::Array);
    prop_oneof![
        2 => number(),
        1 => (number(), number(), number(), number()).prop_map(|(s, e, f, t)| {
            table(&[("kind", "smoothstep".into()), ("start", s), ("end", e), ("from", f), ("to", t)])
        }),
        1 => (list(), list()).prop_map(|(t, v)| {
            table(&[("kind", "piecewise-constant".into()), ("times", t), ("values", v)])
        }),
        1 => (list(), list()).prop_map(|(t, v)| {
            table(&[("kind", "piecewise-linear".into()), ("times", t), ("values", v)])
        }),
        1 => number().prop_map(|v| table(&[("kind", "constant".into()), ("value", v)])),
        1 => Just(table(&[("kind", "spline".into())])),
        1 => wrong_type(),
    ]
}

fn table(pairs: &[(&str, toml::Value)]) -> toml::Value {
    toml::Value::Table(
        pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.clone()))
            .collect(),
    )
}

/// A complete, valid scene, which the mutations below break: the shipped case study with a
/// reference column.
fn base() -> toml::Table {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenes/case-study.toml");
    let mut doc: toml::Table = std::fs::read_to_string(path)
        .expect("the shipped scene")
        .parse()
        .expect("the shipped scene is TOML");
    doc.insert(
        "reference".into(),
        toml::Value::Array(vec![table(&[
            ("label", "paper".into()),
            (
                "frequencies_hz",
                toml::Value::Array(vec![0.53.into(), 6.35.into()]),
            ),
        ])]),
    );
    doc
}

/// Every field of the schema, by its path of table keys, and what kind of value it takes.
#[derive(Debug, Clone, Copy)]
enum Kind {
    Number,
    Count,
    Profile,
    Text,
}

const FIELDS: [(&[&str], Kind); 24] = [
    (&["name"], Kind::Text),
    (&["description"], Kind::Text),
    (&["sections", "count"], Kind::Count),
    (&["sections", "length"], Kind::Number),
    (&["sections", "area"], Kind::Number),
    (&["sections", "inertia"], Kind::Number),
    (&["sections", "density"], Kind::Number),
    (&["sections", "youngs_modulus"], Kind::Number),
    (&["sections", "modes"], Kind::Count),
    (&["masses", "vehicle"], Kind::Number),
    (&["masses", "load"], Kind::Number),
    (&["gravity", "g"], Kind::Number),
    (&["gravity", "force_flow"], Kind::Text),
    (&["contact", "points"], Kind::Count),
    (&["contact", "stiffness"], Kind::Number),
    (&["contact", "damping"], Kind::Number),
    (&["contact", "clearance"], Kind::Number),
    (&["telescope", "positions"], Kind::Profile),
    (&["drive", "force"], Kind::Profile),
    (&["drive", "motion"], Kind::Profile),
    (&["time", "start"], Kind::Number),
    (&["time", "end"], Kind::Number),
    (&["time", "sample"], Kind::Number),
    (&["reference"], Kind::Number),
];

/// One change to a document.
#[derive(Debug, Clone)]
enum Mutation {
    /// Replace (or add) the field `FIELDS[i]` with a value.
    Set(usize, toml::Value),
    /// Remove the field `FIELDS[i]`.
    Remove(usize),
    /// Add an unknown key to the table holding `FIELDS[i]`.
    Unknown(usize, String),
}

/// A value for a field of `kind`: of its kind with edge values, as a list, or of a wrong type.
fn value_for(kind: Kind) -> BoxedStrategy<toml::Value> {
    let text = prop_oneof![
        Just(toml::Value::String("none".into())),
        Just(toml::Value::String("external".into())),
        Just(toml::Value::String(String::new())),
        "[ -~]{0,12}".prop_map(toml::Value::String),
        number(),
    ];
    match kind {
        Kind::Number => value(number()).boxed(),
        Kind::Count => value(count()).boxed(),
        Kind::Profile => prop_oneof![
            3 => prop::collection::vec(profile(), 0..4).prop_map(toml::Value::Array),
            1 => profile(),
        ]
        .boxed(),
        Kind::Text => text.boxed(),
    }
}

fn mutation() -> impl Strategy<Value = Mutation> {
    (0..FIELDS.len()).prop_flat_map(|i| {
        prop_oneof![
            6 => value_for(FIELDS[i].1).prop_map(move |v| Mutation::Set(i, v)),
            2 => Just(Mutation::Remove(i)),
            1 => "[a-z_]{1,8}".prop_map(move |k| Mutation::Unknown(i, k)),
        ]
    })
}

/// The table that holds field `path` (created when missing), or `None` when a value of
/// another type is in the way.
fn parent<'a>(doc: &'a mut toml::Table, path: &[&str]) -> Option<&'a mut toml::Table> {
    let mut t = doc;
    for key in &path[..path.len() - 1] {
        t = t
            .entry(key.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()))
            .as_table_mut()?;
    }
    Some(t)
}

/// A scene document from the schema: the valid base with 0 to 4 random mutations.
fn document() -> impl Strategy<Value = toml::Table> {
    prop::collection::vec(mutation(), 0..5).prop_map(|mutations| {
        let mut doc = base();
        for m in mutations {
            let (i, change) = match &m {
                Mutation::Set(i, _) | Mutation::Remove(i) | Mutation::Unknown(i, _) => {
                    (*i, m.clone())
                }
            };
            let path = FIELDS[i].0;
            let last = path[path.len() - 1];
            let Some(t) = parent(&mut doc, path) else {
                continue;
            };
            match change {
                Mutation::Set(_, v) => {
                    t.insert(last.to_string(), v);
                }
                Mutation::Remove(_) => {
                    t.remove(last);
                }
                Mutation::Unknown(_, k) => {
                    t.insert(k, toml::Value::Integer(1));
                }
            }
        }
        doc
    })
}

/// `--set` arguments: known and unknown keys, indices, TOML and non-TOML values, no `=`.
fn overrides() -> impl Strategy<Value = Vec<String>> {
    let key = prop_oneof![
        Just("sections.count".to_string()),
        Just("sections.modes".to_string()),
        Just("sections.length.1".to_string()),
        Just("sections.length.99".to_string()),
        Just("contact.points".to_string()),
        Just("contact.clearance".to_string()),
        Just("time.sample".to_string()),
        Just("telescope.positions.0.to".to_string()),
        Just("drive.force".to_string()),
        Just("gravity.force_flow".to_string()),
        Just("name.first".to_string()),
        "[a-z.0-9]{0,12}",
    ];
    let value = prop_oneof![
        Just("1e12".to_string()),
        Just("-1".to_string()),
        Just("nan".to_string()),
        Just("inf".to_string()),
        Just("[1, 2, 3]".to_string()),
        Just("{ kind = \"smoothstep\" }".to_string()),
        Just("1000000000000".to_string()),
        Just("none".to_string()),
        "[ -~]{0,16}",
    ];
    let argument = prop_oneof![
        8 => (key, value).prop_map(|(k, v)| format!("{k}={v}")),
        1 => "[ -~]{0,16}",
    ];
    prop::collection::vec(argument, 0..3)
}

/// Loads `text` with `overrides`, checking the allocation peak; returns the result.
fn load(text: &str, overrides: &[String]) -> Result<Scene, SceneError> {
    // one measurement at a time: the tests of this file run on several threads
    static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _turn = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let before = LIVE.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let result = Scene::from_toml_str(text, Path::new("fuzz.toml"), overrides);
    let peak = PEAK.load(Ordering::Relaxed) - before;
    assert!(
        peak <= ALLOCATION_BOUND,
        "loading held {peak} bytes at once (bound {ALLOCATION_BOUND}):\n{text}\n{overrides:?}"
    );
    result
}

/// The error names what it concerns: a known field, a line of the file, or the argument.
fn assert_named(err: &SceneError, text: &str) {
    let message = err.to_string();
    match err {
        SceneError::Invalid { errors, .. } => {
            assert!(!errors.is_empty(), "{message}");
            for e in errors {
                let top = e.field.split(['.', '[']).next().unwrap_or("");
                assert!(
                    TABLES.contains(&top) || top == "drive" || top == "contact",
                    "a rule names an unknown field `{}`: {message}\n{text}",
                    e.field
                );
                assert!(!e.rule.is_empty(), "{message}");
            }
        }
        SceneError::Schema {
            field, message: m, ..
        } => {
            // at the root the message itself names the missing or unknown key
            assert!(
                !field.is_empty() && (field != "." || m.contains('`')),
                "a schema error names no field: {message}\n{text}"
            );
        }
        SceneError::Syntax { message: m, .. } => {
            assert!(m.contains("line") || m.contains("TOML"), "{message}");
        }
        SceneError::Override { argument, rule } => {
            assert!(
                !rule.is_empty() && message.contains(argument.as_str()),
                "{message}"
            );
        }
        SceneError::Io { .. } => panic!("no file is read: {message}"),
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 10_000, ..ProptestConfig::default() })]

    #[test]
    fn schema_documents_load_or_name_the_field(doc in document(), set in overrides()) {
        let text = toml::to_string(&doc).expect("a table serializes");
        match load(&text, &set) {
            Ok(scene) => {
                // what loads is within the documented limits
                prop_assert!((1..=telescopic_runtime::scene::limits::MAX_SECTIONS)
                    .contains(&scene.params.sections.len()));
                prop_assert!(scene.params.sections.iter().all(|s| s.mass_per_length > 0.0
                    && s.mass_per_length.is_finite() && s.bending_stiffness.is_finite()));
                prop_assert!(scene.time.end > scene.time.start && scene.time.sample > 0.0);
            }
            Err(e) => assert_named(&e, &text),
        }
    }

    #[test]
    fn random_bytes_are_rejected_cleanly(bytes in prop::collection::vec(any::<u8>(), 0..512)) {
        let text = String::from_utf8_lossy(&bytes);
        if let Err(e) = load(&text, &[]) {
            assert_named(&e, &text);
        }
    }

    #[test]
    fn overrides_on_a_valid_scene_load_or_name_the_field(set in overrides()) {
        let text = toml::to_string(&base()).expect("a table serializes");
        if let Err(e) = load(&text, &set) {
            assert_named(&e, &text);
        }
    }
}

#[test]
fn the_generated_documents_reach_every_outcome() {
    // the properties above mean something only if the generator makes loadable scenes and
    // each kind of rejection, not just one kind of failure
    use proptest::strategy::ValueTree;
    use proptest::test_runner::TestRunner;
    let mut runner = TestRunner::deterministic();
    let (mut ok, mut invalid, mut schema, mut over) = (0, 0, 0, 0);
    let strategy = (document(), overrides());
    for _ in 0..3000 {
        let (doc, set) = strategy.new_tree(&mut runner).unwrap().current();
        let text = toml::to_string(&doc).unwrap();
        match load(&text, &set) {
            Ok(_) => ok += 1,
            Err(SceneError::Invalid { .. }) => invalid += 1,
            Err(SceneError::Schema { .. }) => schema += 1,
            Err(SceneError::Override { .. }) => over += 1,
            Err(e) => panic!("unexpected: {e}"),
        }
    }
    eprintln!("loaded {ok}, invalid {invalid}, schema {schema}, override {over}");
    assert!(ok >= 3 && invalid >= 100 && schema >= 100 && over >= 10);
}
