//! The rules for input values, written once. Every description a user
//! gives (a material, a rod, contact, damping and solver settings) has a
//! `check()` that applies them and names the offending parameter by its
//! scene-file key; the builder, the scene file and the Python package call
//! the same `check()`, so a value is refused for the same reason whichever
//! way it came in.

/// A parameter that a description cannot take.
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterError {
    /// The parameter, as the scene file names it (`poisson_ratio`,
    /// `radius`; a vector's component as `center[2]`).
    pub field: String,
    /// What is wrong with it.
    pub message: String,
}

impl std::fmt::Display for ParameterError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: {}", self.field, self.message)
    }
}
impl std::error::Error for ParameterError {}

/// `Err` for `field` with `message`.
pub fn refuse<T>(field: &'static str, message: impl Into<String>) -> Result<T, ParameterError> {
    Err(ParameterError {
        field: field.into(),
        message: message.into(),
    })
}

/// A finite number.
pub fn finite(field: &'static str, v: f64) -> Result<f64, ParameterError> {
    if v.is_finite() {
        Ok(v)
    } else {
        refuse(field, format!("must be a finite number, got {v}"))
    }
}

/// A finite number > 0.
pub fn positive(field: &'static str, v: f64) -> Result<f64, ParameterError> {
    finite(field, v)?;
    if v > 0.0 {
        Ok(v)
    } else {
        refuse(field, format!("must be > 0, got {v}"))
    }
}

/// A finite number ≥ 0.
pub fn non_negative(field: &'static str, v: f64) -> Result<f64, ParameterError> {
    finite(field, v)?;
    if v >= 0.0 {
        Ok(v)
    } else {
        refuse(field, format!("must be ≥ 0, got {v}"))
    }
}

/// Three finite numbers; an error names the component (`force[2]`).
pub fn finite3(field: &'static str, v: [f64; 3]) -> Result<[f64; 3], ParameterError> {
    match v.iter().position(|x| !x.is_finite()) {
        None => Ok(v),
        Some(i) => Err(ParameterError {
            field: format!("{field}[{i}]"),
            message: format!("must be a finite number, got {}", v[i]),
        }),
    }
}

/// Three finite numbers, not all zero (a direction).
pub fn direction(field: &'static str, v: [f64; 3]) -> Result<[f64; 3], ParameterError> {
    finite3(field, v)?;
    if v.iter().all(|x| *x == 0.0) {
        refuse(field, "must not be the zero vector")
    } else {
        Ok(v)
    }
}

/// A relative tolerance: in (0, 1).
pub fn relative_tolerance(field: &'static str, t: f64) -> Result<f64, ParameterError> {
    let t = positive(field, t)?;
    if t >= 1.0 {
        return refuse(field, format!("a relative tolerance must be < 1, got {t}"));
    }
    Ok(t)
}

/// A count within `range`.
pub fn count_in(
    field: &'static str,
    n: usize,
    range: std::ops::RangeInclusive<usize>,
) -> Result<usize, ParameterError> {
    if range.contains(&n) {
        Ok(n)
    } else {
        refuse(
            field,
            format!("must be {}..={}, got {n}", range.start(), range.end()),
        )
    }
}
