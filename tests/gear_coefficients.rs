//! Gear's corrector tables derived here, in exact rational arithmetic, from
//! the order conditions of the multistep formula each Nordsieck component
//! obeys (Gear 1971, ch. 9: a Nordsieck method is a multistep method in
//! other coordinates), and compared with the code's tables bit for bit; then
//! one step of the code's own predictor-corrector on polynomial data is shown
//! to be those formulas.
//!
//! With `h = 1`, the new values at `s = 0` and the past ones at `s = -1, -2,
//! ...`, a correction `r_j <- r_j + c_j delta` changes `r_j` in proportion to
//! the newest right-hand side (`delta = f(0) - predicted` for first-order
//! equations, `delta = f(0)/2 - predicted` for second-order ones, whose `r_2`
//! is `y''/2`). So `c_j` is the weight of the newest value in the formula
//! that gives `r_j` (times 2 for second-order equations). The formulas, each
//! fixed by exactness on monomials `s^k`:
//!
//! * first order, 5 values (`q = 4`): `r_0` by the 4-step Adams-Moulton
//!   formula `y(0) - y(-1) = sum_{m=0..4} w_m y'(-m)` (exact to degree 5);
//!   `r_j = y^(j)(0)/j!`, `j = 1..4`, of the polynomial whose derivative
//!   interpolates the 4 newest `y'` (exact to degree 4);
//! * second order, 6 values (`q = 5`): `r_j`, `j = 2..5`, likewise from the
//!   4 newest `y''`; `r_1 = y'(0)` by the Adams-Moulton formula on the 5
//!   newest `y''`, `y'(0) - y'(-1) = sum_{m=0..4} a_m y''(-m)` (exact to
//!   degree 6); `r_0` either from the previous position and velocity with the
//!   same 5 accelerations, `y(0) - y(-1) - y'(-1) = sum_{m=0..4} b_m y''(-m)`
//!   (exact to degree 6: position and velocity advance by one acceleration
//!   polynomial, as they must when the force depends on the velocity), giving
//!   `c0 = 3/16`; or, for position-only forces, by the Stormer-Cowell formula
//!   `y(0) - 2 y(-1) + y(-2) = sum_{m=0..5} s_m y''(-m)` (exact to degree 7,
//!   one order more), giving `c0 = 3/20`.

use nalgebra::Vector3;
use quatrot::integrators::gear::{
    second_order_6, Nordsieck, C0_POSITION_ONLY, C0_VELOCITY_DEPENDENT, FIRST_ORDER_5,
};
use quatrot::integrators::FirstCorrector;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// A reduced fraction `num / den` with `den > 0`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Ratio {
    num: i128,
    den: i128,
}

fn gcd(a: i128, b: i128) -> i128 {
    if b == 0 {
        a.abs()
    } else {
        gcd(b, a % b)
    }
}

impl Ratio {
    const ZERO: Ratio = Ratio { num: 0, den: 1 };

    fn new(num: i128, den: i128) -> Ratio {
        assert!(den != 0, "zero denominator");
        let g = gcd(num, den) * den.signum();
        Ratio {
            num: num / g,
            den: den / g,
        }
    }

    fn int(n: i128) -> Ratio {
        Ratio::new(n, 1)
    }

    /// The nearest `f64` (both parts are below 2^53, so the quotient of their
    /// exact `f64` values is correctly rounded).
    fn to_f64(self) -> f64 {
        const EXACT: i128 = 1 << 53;
        assert!(self.num.abs() < EXACT && self.den < EXACT, "{self:?}");
        self.num as f64 / self.den as f64
    }
}

impl Add for Ratio {
    type Output = Ratio;
    fn add(self, o: Ratio) -> Ratio {
        Ratio::new(self.num * o.den + o.num * self.den, self.den * o.den)
    }
}

impl Sub for Ratio {
    type Output = Ratio;
    fn sub(self, o: Ratio) -> Ratio {
        self + -o
    }
}

impl Neg for Ratio {
    type Output = Ratio;
    fn neg(self) -> Ratio {
        Ratio::new(-self.num, self.den)
    }
}

impl Mul for Ratio {
    type Output = Ratio;
    fn mul(self, o: Ratio) -> Ratio {
        Ratio::new(self.num * o.num, self.den * o.den)
    }
}

impl Div for Ratio {
    type Output = Ratio;
    fn div(self, o: Ratio) -> Ratio {
        Ratio::new(self.num * o.den, self.den * o.num)
    }
}

/// The `d`-th derivative of `s^k` at the integer `s`.
fn monomial(k: u32, d: u32, s: i128) -> Ratio {
    if d > k {
        return Ratio::ZERO;
    }
    let falling: i128 = (k - d + 1..=k).map(i128::from).product();
    Ratio::int(falling * s.pow(k - d))
}

/// Solves `a x = b` by Gaussian elimination (exact, so any non-zero pivot).
fn solve(mut a: Vec<Vec<Ratio>>, mut b: Vec<Ratio>) -> Vec<Ratio> {
    let n = b.len();
    for col in 0..n {
        let pivot = (col..n)
            .find(|&r| a[r][col] != Ratio::ZERO)
            .expect("the order conditions are independent");
        a.swap(col, pivot);
        b.swap(col, pivot);
        let (pivot_row, pivot_rhs) = (a[col].clone(), b[col]);
        for (row, rhs) in a.iter_mut().zip(b.iter_mut()).skip(col + 1) {
            let f = row[col] / pivot_row[col];
            for (x, p) in row.iter_mut().zip(&pivot_row).skip(col) {
                *x = *x - f * *p;
            }
            *rhs = *rhs - f * pivot_rhs;
        }
    }
    // Back substitution on the upper-triangular system.
    let mut x = vec![Ratio::ZERO; n];
    for i in (0..n).rev() {
        let known = (i + 1..n).fold(Ratio::ZERO, |acc, j| acc + a[i][j] * x[j]);
        x[i] = (b[i] - known) / a[i][i];
    }
    x
}

/// A formula for a scaled derivative `r_j = y^(j)(0)/j!` at the new time:
/// `r_j = previous[y] + sum_{m=0..nodes} w_m y^(d)(-m)` (`d` the order of the
/// equation), exact for `y = s^k`, `k = d..d + nodes`: its order conditions
/// fix the weights.
struct Formula {
    j: u32,
    /// The part from the past state (`y(-1)`, `y'(-1)`, ...), for `y = s^k`.
    previous: fn(u32) -> Ratio,
    d: u32,
    nodes: usize,
}

impl Formula {
    /// The weights `w_m`, by solving the order conditions.
    fn weights(&self) -> Vec<Ratio> {
        let powers: Vec<u32> = (self.d..).take(self.nodes).collect();
        let a = powers
            .iter()
            .map(|&k| {
                (0..self.nodes)
                    .map(|m| monomial(k, self.d, -(m as i128)))
                    .collect()
            })
            .collect();
        // r_j of s^k at s = 0 is 1 for k = j and 0 otherwise.
        let rhs = powers
            .iter()
            .map(|&k| Ratio::int(i128::from(k == self.j)) - (self.previous)(k))
            .collect();
        solve(a, rhs)
    }

    /// The weight of the newest value, `w_0`.
    fn newest(&self) -> Ratio {
        self.weights()[0]
    }

    /// `r_j` at `s = 0` by the formula, for `y = s^k`.
    fn apply(&self, k: u32) -> f64 {
        let sum = self
            .weights()
            .iter()
            .enumerate()
            .fold((self.previous)(k), |acc, (m, w)| {
                acc + *w * monomial(k, self.d, -(m as i128))
            });
        sum.to_f64()
    }
}

fn nothing(_: u32) -> Ratio {
    Ratio::ZERO
}

/// First order, `q + 1` values: the formula of `r_j` (module doc).
fn first_order_formula(q: usize, j: u32) -> Formula {
    match j {
        0 => Formula {
            j,
            previous: |k| monomial(k, 0, -1),
            d: 1,
            nodes: q + 1,
        },
        _ => Formula {
            j,
            previous: nothing,
            d: 1,
            nodes: q,
        },
    }
}

/// How the position of a second-order method advances (module doc).
#[derive(Clone, Copy, Debug)]
enum Position {
    /// From the previous position and velocity with the velocity's
    /// accelerations (forces that depend on the velocity).
    WithVelocity,
    /// By the Stormer-Cowell formula (forces of the position only).
    Stormer,
}

/// Second order, `q + 1` values: the formula of `r_j` (module doc).
fn second_order_formula(q: usize, j: u32, position: Position) -> Formula {
    let (previous, nodes): (fn(u32) -> Ratio, usize) = match (j, position) {
        (0, Position::WithVelocity) => (|k| monomial(k, 0, -1) + monomial(k, 1, -1), q),
        (0, Position::Stormer) => (
            |k| Ratio::int(2) * monomial(k, 0, -1) - monomial(k, 0, -2),
            q + 1,
        ),
        (1, _) => (|k| monomial(k, 1, -1), q),
        _ => (nothing, q - 1),
    };
    Formula {
        j,
        previous,
        d: 2,
        nodes,
    }
}

/// The first-order table with 5 values: the newest weights.
fn first_order_table() -> [Ratio; 5] {
    std::array::from_fn(|j| first_order_formula(4, j as u32).newest())
}

/// The second-order table with 6 values: twice the newest weights.
fn second_order_table(position: Position) -> [Ratio; 6] {
    std::array::from_fn(|j| Ratio::int(2) * second_order_formula(5, j as u32, position).newest())
}

fn assert_table<const N: usize>(what: &str, derived: [Ratio; N], code: [f64; N]) {
    let as_f64 = derived.map(Ratio::to_f64);
    assert_eq!(
        as_f64.map(f64::to_bits),
        code.map(f64::to_bits),
        "{what}: derived {derived:?} = {as_f64:?}, code {code:?}"
    );
}

/// The tables of `gear.rs` are the derived ones, bit for bit; the values are
/// Gear's (251/720, 1, 11/12, 1/3, 1/24 and c0, 251/360, 1, 11/18, 1/6, 1/60).
#[test]
fn corrector_tables_follow_from_the_order_conditions() {
    let first = first_order_table();
    assert_eq!(first[0], Ratio::new(251, 720));
    assert_table("first order, 5 values", first, FIRST_ORDER_5);
    let with_velocity = second_order_table(Position::WithVelocity);
    let stormer = second_order_table(Position::Stormer);
    assert_eq!(
        (with_velocity[0], stormer[0]),
        (Ratio::new(3, 16), Ratio::new(3, 20))
    );
    assert_eq!(with_velocity[1..], stormer[1..]);
    assert_table(
        "second order, velocity-dependent forces",
        with_velocity,
        second_order_6(C0_VELOCITY_DEPENDENT),
    );
    assert_table(
        "second order, position-only forces",
        stormer,
        second_order_6(C0_POSITION_ONLY),
    );
    // The scene's two choices of scheme B's c0 (`first_corrector`) are the
    // derived values, named by their fractions.
    for (choice, derived) in [
        (FirstCorrector::VelocityDependent, with_velocity[0]),
        (FirstCorrector::PositionOnly, stormer[0]),
    ] {
        assert_eq!(choice.as_str(), format!("{}/{}", derived.num, derived.den));
        assert_eq!(
            choice.value().to_bits(),
            derived.to_f64().to_bits(),
            "{}",
            choice.as_str()
        );
    }
}

/// The same formulas give Gear's other published first-order tables
/// (3, 4 and 6 values) and the 5-value second-order `c0` (19/90 and
/// 19/120): the conditions, not tuned numbers, produce the family.
#[test]
fn order_conditions_reproduce_gears_other_tables() {
    let table = |q: usize| -> Vec<Ratio> {
        (0..=q as u32)
            .map(|j| first_order_formula(q, j).newest())
            .collect()
    };
    let r = Ratio::new;
    assert_eq!(table(2), [r(5, 12), r(1, 1), r(1, 2)]);
    assert_eq!(table(3), [r(3, 8), r(1, 1), r(3, 4), r(1, 6)]);
    assert_eq!(
        table(5),
        [
            r(95, 288),
            r(1, 1),
            r(25, 24),
            r(35, 72),
            r(5, 48),
            r(1, 120)
        ]
    );
    let c0 = |position| Ratio::int(2) * second_order_formula(4, 0, position).newest();
    assert_eq!(
        (c0(Position::WithVelocity), c0(Position::Stormer)),
        (r(19, 90), r(19, 120))
    );
}

/// Round-off of a step of the recursion on values up to ~1e3 (relative to
/// the largest value; measured ~1e-16).
const RECURSION_ROUND_OFF: f64 = 1e-13;

/// One predict-correct step of the code's recursion (`table`, equation of
/// order `d`), from the data the formulas describe at `s = -1` (value and
/// lower derivatives exact, higher derivatives interpolating the previous
/// right-hand sides), gives what the formulas give at `s = 0`, for `y = s^k`.
fn check_step<const N: usize>(table: &[f64; N], d: u32, formula: impl Fn(u32) -> Formula, k: u32) {
    // The formulas are translation invariant: at s = -1 they read y = (s - 1)^k
    // at s = 0, which is what the derivatives interpolate there.
    let shifted = |j: usize| -> f64 {
        let j = j as u32;
        if j < d {
            return monomial(k, j, -1).to_f64();
        }
        let f = formula(j);
        f.weights()
            .iter()
            .enumerate()
            .fold(Ratio::ZERO, |acc, (m, w)| {
                acc + *w * monomial(k, d, -1 - m as i128)
            })
            .to_f64()
    };
    let mut n = Nordsieck::<Vector3<f64>, N>::zeros(1);
    n.set_rotor(0, &std::array::from_fn(|j| Vector3::repeat(shifted(j))));
    n.predict();
    // delta = h^d/d! f(0) - predicted r_d, with f = y^(d).
    let newest = monomial(k, d, 0).to_f64() / if d == 1 { 1.0 } else { 2.0 };
    let delta = Vector3::repeat(newest) - n.r[d as usize][0];
    n.correct(0, table, delta);
    let expected: [f64; N] = std::array::from_fn(|j| formula(j as u32).apply(k));
    let largest = expected.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    for (j, (got, want)) in n.rotor(0).iter().zip(&expected).enumerate() {
        assert!(
            (got.x - want).abs() < RECURSION_ROUND_OFF * largest,
            "s^{k}, r_{j}: recursion {} vs formula {want}",
            got.x
        );
    }
}

/// scheme A's recursion (`FIRST_ORDER_5`) is the 4-step Adams-Moulton formula
/// for the value and the interpolating polynomial for the derivatives, on
/// `y = s^k` up to degree 5 (where the correction is largest).
#[test]
fn first_order_step_is_adams_moulton() {
    for k in 1..=5 {
        check_step(&FIRST_ORDER_5, 1, |j| first_order_formula(4, j), k);
    }
}

/// scheme B's recursion with `c0 = 3/16` advances velocity and position by
/// one acceleration polynomial (Adams-Moulton for the velocity, the Taylor
/// remainder for the position), on `y = s^k` up to degree 6.
#[test]
fn second_order_step_advances_position_and_velocity_together() {
    let table = second_order_6(C0_VELOCITY_DEPENDENT);
    for k in 2..=6 {
        check_step(
            &table,
            2,
            |j| second_order_formula(5, j, Position::WithVelocity),
            k,
        );
    }
}
