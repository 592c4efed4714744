//! Model files that are large on purpose (issue 25's hostile inputs, and natural large ones),
//! shared by the load-cost tests and the loading benchmark.

#![allow(dead_code)]

/// The 20 coordinates of the wide models (`t` is the time).
pub fn coordinates() -> Vec<String> {
    ('a'..='u')
        .filter(|&c| c != 't')
        .map(String::from)
        .collect()
}

/// A valid 20-coordinate model whose Lagrangian is `½ Σ q̇ᵢ² + 10⁻⁶ (Σ q̇ᵢ)² · a·b·c·…` with
/// `factors` factors, and `constraints` constraints `qⱼ + h0 ≥ 0`.
pub fn wide(factors: usize, constraints: usize) -> String {
    let q = coordinates();
    let squares: Vec<String> = q.iter().map(|c| format!("{c}_dot^2")).collect();
    let velocities: Vec<String> = q.iter().map(|c| format!("{c}_dot")).collect();
    let product: Vec<&str> = (0..factors).map(|i| q[i % q.len()].as_str()).collect();
    let mut file = format!(
        "name = \"wide\"\ncoordinates = [{}]\nlagrangian = \"0.5*({}) + 1e-6*({})^2 * {}\"\n\
         [parameters]\nh0 = 1.0\n",
        q.iter()
            .map(|c| format!("\"{c}\""))
            .collect::<Vec<_>>()
            .join(", "),
        squares.join("+"),
        velocities.join("+"),
        product.join("*"),
    );
    for j in 0..constraints {
        file += &format!(
            "[[constraint]]\nname = \"c{j}\"\nh = \"{} + h0\"\nrestitution = 0.5\n",
            q[j % q.len()]
        );
    }
    file += "[initial]\n";
    for c in &q {
        file += &format!("{c} = 0.5\n");
    }
    file
}

/// `count` parameters, each the one before plus 1 (`p0 = 1`), and a model that uses the last.
pub fn parameter_chain(count: usize) -> String {
    let mut source = String::from(
        "name = \"chain\"\ncoordinates = [\"y\"]\nlagrangian = \"0.5*y_dot^2 - y\"\n\
         [parameters]\np0 = 1.0\n",
    );
    for i in 1..count {
        source += &format!("p{i} = \"p{} + 1\"\n", i - 1);
    }
    source += &format!(
        "[[constraint]]\nname = \"floor\"\nh = \"y + p{}\"\nrestitution = 0.5\n[initial]\ny = 1\n",
        count - 1
    );
    source
}

/// A planar chain of `links` pendulums (unit masses, links of 0.1 m) against a wall, its
/// Lagrangian written out in full: a dense mass matrix, each entry a sum of cosines.
pub fn pendulum_chain(links: usize) -> String {
    let th: Vec<String> = (0..links).map(|i| format!("th{i}")).collect();
    let sum = |f: &dyn Fn(usize) -> String, i: usize| (0..=i).map(f).collect::<Vec<_>>().join("+");
    let terms: Vec<String> = (0..links)
        .map(|i| {
            let vx = sum(&|k| format!("cos({0})*{0}_dot", th[k]), i);
            let vy = sum(&|k| format!("sin({0})*{0}_dot", th[k]), i);
            let y = sum(&|k| format!("cos({})", th[k]), i);
            format!("0.5*m*l^2*(({vx})^2+({vy})^2) + m*g*l*({y})")
        })
        .collect();
    let mut file = format!(
        "name = \"chain{links}\"\ncoordinates = [{}]\nlagrangian = \"{}\"\n\
         [parameters]\nm = 1.0\nl = 0.1\ng = 9.81\n\
         [[constraint]]\nname = \"wall\"\nh = \"1 - th0\"\nrestitution = 0.5\n[initial]\n",
        th.iter()
            .map(|c| format!("\"{c}\""))
            .collect::<Vec<_>>()
            .join(", "),
        terms.join(" + "),
    );
    for c in &th {
        file += &format!("{c} = 0.1\n");
    }
    file
}

/// The kinetic energy `½ Σ q̇ᵢ²` of the wide models' 20 coordinates, and their list.
fn head(name: &str) -> String {
    let q = coordinates();
    let squares: Vec<String> = q.iter().map(|c| format!("{c}_dot^2")).collect();
    let list: Vec<String> = q.iter().map(|c| format!("\"{c}\"")).collect();
    format!(
        "name = \"{name}\"\ncoordinates = [{}]\nlagrangian = \"0.5*({})\"\n",
        list.join(", "),
        squares.join("+")
    )
}

/// The initial state of the wide models: every coordinate at 0.5, at rest.
fn at_half() -> String {
    let mut file = String::from("[initial]\n");
    for c in coordinates() {
        file += &format!("{c} = 0.5\n");
    }
    file
}

/// A review's attack on the limit through the programs made from the trace: a constant `M`,
/// on each of the 20 coordinates a force `q·q·…` of `factors` factors, and `constraints`
/// constraints `qⱼ + 1 ≥ 0` (each constraint's programs hold the whole force).
pub fn forces(factors: usize, constraints: usize) -> String {
    let mut file = head("forces");
    for j in 0..constraints {
        let q = &coordinates()[j % 20];
        file += &format!("[[constraint]]\nname = \"c{j}\"\nh = \"{q} + 1\"\nrestitution = 0.5\n");
    }
    file += "[forces]\n";
    for q in coordinates() {
        file += &format!("{q} = \"{}\"\n", vec![q.as_str(); factors].join("*"));
    }
    file + &at_half()
}

/// A review's attack on the limit through new entries: a constant `M`, and `constraints`
/// constraints, each `h` a product of `factors` coordinates (shifted by one per constraint,
/// so that nothing is shared) plus 1.
pub fn products(factors: usize, constraints: usize) -> String {
    let q = coordinates();
    let mut file = head("products");
    for j in 0..constraints {
        let product: Vec<&str> = (0..factors).map(|i| q[(i + j) % 20].as_str()).collect();
        file += &format!(
            "[[constraint]]\nname = \"c{j}\"\nh = \"{} + 1\"\nrestitution = 0.5\n",
            product.join("*")
        );
    }
    file + &at_half()
}
