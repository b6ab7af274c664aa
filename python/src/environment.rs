//! The environment variables the package reads.

/// The environment variable that sets the calls' memory budget (bytes, or `512M`, `16G`).
pub const MEMORY_BUDGET_VARIABLE: &str = "TELESCOPIC_MEMORY_BUDGET";
