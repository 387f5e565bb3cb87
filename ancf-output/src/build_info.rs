//! What this program was built from: its version, the git commit (and
//! whether the work tree differed from it), the compiler and the axial
//! quadrature orders with generated kernels (the package's build script
//! records the first three). `ancf --version`, summary.json and the Python
//! package's `summary()` report it.

use serde::Serialize;

/// The build provenance of the running program.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BuildInfo {
    /// The package version.
    pub version: &'static str,
    /// The git commit built from, or "unknown" (no git, a source tarball).
    pub commit: &'static str,
    /// Whether tracked files differed from the commit.
    pub dirty: bool,
    /// `rustc --version` of the compiler.
    pub rustc: &'static str,
    /// Axial quadrature orders with generated (unrolled) element kernels.
    pub kernel_orders: Vec<usize>,
}

impl BuildInfo {
    /// This program's.
    pub fn current() -> Self {
        BuildInfo {
            version: env!("CARGO_PKG_VERSION"),
            commit: env!("ANCF_GIT_COMMIT"),
            dirty: env!("ANCF_GIT_DIRTY") == "true",
            rustc: env!("ANCF_RUSTC_VERSION"),
            kernel_orders: ancf_core::element::COMPILED_AXIAL_ORDERS.to_vec(),
        }
    }

    /// One line: `0.1.0 (commit 205d375…, dirty; rustc 1.95.0 …; kernels for axial orders 2,3,4,5)`.
    pub fn line(&self) -> String {
        let orders: Vec<String> = self.kernel_orders.iter().map(|o| o.to_string()).collect();
        format!(
            "{} (commit {}{}; {}; kernels for axial orders {})",
            self.version,
            self.commit,
            if self.dirty { ", dirty" } else { "" },
            self.rustc,
            orders.join(",")
        )
    }
}

impl Default for BuildInfo {
    /// This program's: a summary made with defaults still says what made it.
    fn default() -> Self {
        BuildInfo::current()
    }
}

/// [`BuildInfo::line`] of this program, made once (clap's `--version`).
pub fn version_line() -> &'static str {
    static LINE: std::sync::LazyLock<String> =
        std::sync::LazyLock::new(|| BuildInfo::current().line());
    LINE.as_str()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_names_every_part() {
        let b = BuildInfo::current();
        let line = b.line();
        assert!(line.starts_with(env!("CARGO_PKG_VERSION")));
        assert!(line.contains(b.commit) && line.contains("rustc"));
        assert!(!b.kernel_orders.is_empty());
        assert!(
            b.commit == "unknown" || b.commit.len() == 40,
            "{}",
            b.commit
        );
    }
}
