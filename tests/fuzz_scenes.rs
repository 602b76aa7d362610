//! A seeded mutation fuzz of scene files (issue 19, item 10): each case
//! takes a built-in scene, applies one to three mutations (hostile numbers,
//! strings and nestings, deleted and unknown keys, duplicated entries),
//! writes it as TOML and runs what `quatrot check` does; a scene it accepts
//! runs three steps (systems of at most [`RUN_MAX_ROTORS`] rotors). Asserted
//! for every case: no panic, no case longer than [`CASE_BOUND`], every
//! error names a field (or the line and column of a syntax error), and no
//! message holds control characters or more than [`MAX_MESSAGE_CHARS`]
//! characters.
//!
//! `make test` runs [`DEFAULT_CASES`] cases from [`DEFAULT_SEED`];
//! `QUATROT_FUZZ_CASES` and `QUATROT_FUZZ_SEED` change them (`make
//! validate` runs 20,000). A failure prints the seed, the case and the scene.

use quatrot::run::{execute, prepare, Outputs};
use quatrot::scene::{load_text, Overrides, BUILTINS};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use toml::Value;

const DEFAULT_CASES: u64 = 2000;
const DEFAULT_SEED: u64 = 19;
/// The memory limit of the fuzz: large systems are refused fast.
const MEMORY_LIMIT: &str = "256M";
/// Accepted scenes of at most this many rotors run three steps.
const RUN_MAX_ROTORS: usize = 2000;
/// The longest a case may take (the slowest seen take about 0.1 s).
const CASE_BOUND: Duration = Duration::from_secs(20);
/// The longest message: a path, a sentence and a short excerpt.
const MAX_MESSAGE_CHARS: usize = 700;

fn env_or(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// A hostile replacement value.
fn hostile(rng: &mut ChaCha8Rng) -> Value {
    const INTS: [i64; 11] = [
        0,
        -1,
        1,
        3,
        i32::MAX as i64,
        u32::MAX as i64,
        1 << 43,
        1 << 62,
        i64::MAX,
        i64::MIN,
        1_000_000,
    ];
    const FLOATS: [f64; 15] = [
        0.0,
        -0.0,
        -1.0,
        5e-324,
        1e-310,
        1e308,
        -1e308,
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        1e10,
        3e10,
        1e-9,
        0.5,
        1e-300,
    ];
    match rng.random_range(0..8) {
        0 => Value::Integer(INTS[rng.random_range(0..INTS.len())]),
        1 | 2 => Value::Float(FLOATS[rng.random_range(0..FLOATS.len())]),
        3 => Value::String(
            [
                "",
                "../../../X",
                "/tmp/abs",
                "a\u{1b}[31mb\n",
                "\u{0}",
                "gear_b",
                "dlm",
                "periodic",
                "open",
                "random",
            ][rng.random_range(0..10)]
            .to_string(),
        ),
        4 => Value::String("x\u{7}".repeat(rng.random_range(1..20_000))),
        5 => Value::Boolean(rng.random()),
        6 => {
            let depth = rng.random_range(1..40);
            (0..depth).fold(Value::Float(1.0), |v, _| Value::Array(vec![v]))
        }
        _ => Value::Array(
            (0..rng.random_range(0..5))
                .map(|_| Value::Float(FLOATS[rng.random_range(0..FLOATS.len())]))
                .collect(),
        ),
    }
}

/// A random place in the tree: a path of table keys and array indices.
fn random_node<'a>(value: &'a mut Value, rng: &mut ChaCha8Rng) -> &'a mut Value {
    let descend = rng.random_bool(0.75);
    let has_children = match value {
        Value::Table(t) => !t.is_empty(),
        Value::Array(a) => !a.is_empty(),
        _ => false,
    };
    if !(descend && has_children) {
        return value;
    }
    match value {
        Value::Table(t) => {
            let k = rng.random_range(0..t.len());
            let key = t.keys().nth(k).cloned().unwrap_or_default();
            random_node(t.get_mut(&key).expect("key exists"), rng)
        }
        Value::Array(a) => {
            let k = rng.random_range(0..a.len());
            random_node(&mut a[k], rng)
        }
        _ => value,
    }
}

/// One mutation at a random place.
fn mutate(scene: &mut Value, rng: &mut ChaCha8Rng) {
    let kind = rng.random_range(0..6);
    let node = random_node(scene, rng);
    match (kind, node) {
        (0, Value::Table(t)) if !t.is_empty() => {
            let k = rng.random_range(0..t.len());
            let key = t.keys().nth(k).cloned().unwrap_or_default();
            let _ = t.remove(&key);
        }
        (1, Value::Table(t)) => {
            let _ = t.insert("unexpected\u{1b}key".to_string(), hostile(rng));
        }
        (2, Value::Array(a)) if !a.is_empty() => {
            let copies = rng.random_range(1..4);
            let first = a[0].clone();
            a.extend(std::iter::repeat_n(first, copies));
        }
        (3, Value::Float(x)) => *x *= 10f64.powi(rng.random_range(-320..320)),
        (3, Value::Integer(x)) => *x = x.saturating_mul(rng.random_range(-3..1_000_000)),
        (_, node) => *node = hostile(rng),
    }
}

/// Whether `message` starts by naming a field (a dotted path of keys with
/// indices, or two such joined by " and "), or the line and column of a
/// syntax error.
fn names_a_field(message: &str) -> bool {
    let message = message.strip_prefix("potential: ").unwrap_or(message);
    if message.starts_with("syntax: line ") {
        return true;
    }
    let Some((path, _)) = message.split_once(": ") else {
        return false;
    };
    path.split(" and ").all(|p| {
        !p.is_empty()
            && p.split('.').all(|part| {
                let name = part.split('[').next().unwrap_or_default();
                // Unknown keys are quoted as written (escaped).
                !name.is_empty() && !name.contains(char::is_whitespace)
            })
    })
}

/// What went wrong with a case, if anything.
fn check_case(text: &str) -> Result<(), String> {
    let judge = |e: String| -> Result<(), String> {
        if !names_a_field(&e) {
            return Err(format!("names no field: {e}"));
        }
        if e.chars().any(char::is_control) {
            return Err(format!("control characters: {e:?}"));
        }
        if e.chars().count() > MAX_MESSAGE_CHARS {
            return Err(format!("{} characters: {e}", e.chars().count()));
        }
        Ok(())
    };
    let scene = match load_text(text, &Overrides::default()) {
        Ok((_, scene)) => scene,
        Err(e) => return judge(e.to_string()),
    };
    if let Err(e) = prepare(&scene, false) {
        return judge(e.to_string());
    }
    if scene.rotors.len() > RUN_MAX_ROTORS {
        return Ok(());
    }
    let short = Overrides {
        steps: Some(3),
        ..Overrides::default()
    };
    let (_, scene) = load_text(text, &short).map_err(|e| format!("shortened: {e}"))?;
    match execute(
        &scene,
        serde_json::Value::Null,
        &Outputs::default(),
        None,
        None,
    ) {
        Ok(_) => Ok(()),
        Err(e) => judge(e.to_string()).and(Err(format!("check accepted, run refused: {e}"))),
    }
}

#[test]
fn mutated_scenes_never_panic_and_every_error_names_a_field() {
    quatrot::internals::set_limit(MEMORY_LIMIT, "the fuzz test").expect("limit set first");
    let cases = env_or("QUATROT_FUZZ_CASES", DEFAULT_CASES);
    let seed = env_or("QUATROT_FUZZ_SEED", DEFAULT_SEED);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let corpus: Vec<Value> = BUILTINS
        .iter()
        .map(|b| Value::Table(toml::from_str(b.toml).expect("built-ins parse")))
        .collect();
    let (mut accepted, mut refused, mut case) = (0, 0, 0);
    // A case that never returns cannot be timed after the fact: a watchdog
    // ends the test with the case's scene once it exceeds the bound.
    let current: Arc<Mutex<Option<(u64, Instant, String)>>> = Arc::new(Mutex::new(None));
    let watched = Arc::clone(&current);
    std::thread::spawn(move || loop {
        std::thread::sleep(Duration::from_millis(500));
        if let Some((case, started, text)) = watched.lock().unwrap().as_ref() {
            if started.elapsed() > CASE_BOUND {
                let excerpt: String = text.chars().take(3000).collect();
                eprintln!(
                    "fuzz seed {seed}, case {case}: still running after {CASE_BOUND:?}\n--- scene ---\n{excerpt}"
                );
                std::process::exit(101);
            }
        }
    });
    while accepted + refused < cases {
        case += 1;
        let mut scene = corpus[rng.random_range(0..corpus.len())].clone();
        for _ in 0..rng.random_range(1..4) {
            mutate(&mut scene, &mut rng);
        }
        // Some mutated trees have no TOML form (a table after a value in an
        // array of tables): drawn again.
        let Ok(text) = toml::to_string(&scene) else {
            continue;
        };
        let started = Instant::now();
        *current.lock().unwrap() = Some((case, started, text.clone()));
        let outcome = catch_unwind(AssertUnwindSafe(|| check_case(&text)));
        let elapsed = started.elapsed();
        *current.lock().unwrap() = None;
        let failure = match outcome {
            Err(_) => Some("panicked".to_string()),
            Ok(Err(why)) => Some(why),
            Ok(Ok(())) if elapsed > CASE_BOUND => Some(format!("took {elapsed:?}")),
            Ok(Ok(())) => None,
        };
        if let Some(why) = failure {
            let excerpt: String = text.chars().take(3000).collect();
            panic!("fuzz seed {seed}, case {case}: {why}\n--- scene ---\n{excerpt}");
        }
        if load_text(&text, &Overrides::default()).is_ok() {
            accepted += 1;
        } else {
            refused += 1;
        }
    }
    eprintln!("fuzz seed {seed}: {cases} cases, {accepted} accepted, {refused} refused");
    assert!(
        refused > 0 && accepted > 0,
        "the mutations exercise both outcomes"
    );
}
