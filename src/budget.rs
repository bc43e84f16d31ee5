//! Memory budgets: jobs whose estimated memory exceeds the budget are refused before
//! they start, naming the estimate. A budget is written as a byte count with an
//! optional binary unit (`4096`, `512MiB`, `8GiB`, `2G`: [`MemoryBudget::from_str`]), as
//! the command line's `--memory-budget` and the Python package's `memory_budget=` take it.

use std::str::FromStr;

use crate::error::{Error, Result};

/// The most memory a job may use, in bytes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MemoryBudget(pub u64);

impl MemoryBudget {
    /// Half the machine's physical memory (read from `/proc/meminfo`), or 4 GiB when
    /// that cannot be read.
    #[must_use]
    pub fn half_of_ram() -> Self {
        let total = std::fs::read_to_string("/proc/meminfo").ok().and_then(|text| {
            let line = text.lines().find(|l| l.starts_with("MemTotal:"))?;
            let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
            Some(kib * 1024)
        });
        MemoryBudget(total.map_or(4 << 30, |t| t / 2))
    }

    /// No limit.
    #[must_use]
    pub fn unlimited() -> Self {
        MemoryBudget(u64::MAX)
    }

    /// The [`Error::OverBudget`] of `job`, which needs at least `estimate` bytes, more
    /// than the budget (found while counting, before the whole estimate is known).
    #[must_use]
    pub fn refusal(&self, job: impl Into<String>, estimate: u64) -> Error {
        Error::OverBudget { job: job.into(), estimate, budget: self.0 }
    }

    /// Fails with [`Error::OverBudget`] when `estimate` exceeds the budget.
    pub fn check(&self, job: impl Into<String>, estimate: u64) -> Result<()> {
        if estimate > self.0 {
            return Err(self.refusal(job, estimate));
        }
        Ok(())
    }
}

impl Default for MemoryBudget {
    fn default() -> Self {
        MemoryBudget::half_of_ram()
    }
}

impl FromStr for MemoryBudget {
    type Err = String;

    /// A byte size such as `4096`, `512MiB`, `8GiB`, `2G`, `1.5GiB`: a number, then
    /// `B`, `K`/`KB`/`KiB`, `M`/`MB`/`MiB`, `G`/`GB`/`GiB` or `T`/`TB`/`TiB` (any case,
    /// all binary: `KB` is 1024 bytes).
    fn from_str(s: &str) -> std::result::Result<Self, String> {
        let s = s.trim();
        let split = s.find(|c: char| !c.is_ascii_digit() && c != '.').unwrap_or(s.len());
        let (num, unit) = s.split_at(split);
        let num: f64 = num.parse().map_err(|_| format!("'{s}' is not a size like 512MiB or 8GiB"))?;
        let scale: u64 = match unit.trim().to_ascii_lowercase().as_str() {
            "" | "b" => 1,
            "k" | "kb" | "kib" => 1 << 10,
            "m" | "mb" | "mib" => 1 << 20,
            "g" | "gb" | "gib" => 1 << 30,
            "t" | "tb" | "tib" => 1 << 40,
            other => return Err(format!("unknown unit '{other}' (use B, KiB, MiB, GiB or TiB)")),
        };
        Ok(MemoryBudget((num * scale as f64) as u64))
    }
}

#[cfg(test)]
mod tests {
    use super::MemoryBudget;

    #[test]
    fn sizes_parse_to_their_bytes() {
        let bytes = |s: &str| s.parse::<MemoryBudget>().map(|b| b.0);
        assert_eq!(bytes("4096"), Ok(4096));
        assert_eq!(bytes("512MiB"), Ok(512 * 1024 * 1024));
        assert_eq!(bytes(" 8gib "), Ok(8 * 1024 * 1024 * 1024));
        assert_eq!(bytes("2G"), Ok(2 * 1024 * 1024 * 1024));
        assert_eq!(bytes("1.5KiB"), Ok(1536));
        assert_eq!(bytes("10 B"), Ok(10));
        assert!(bytes("lots").unwrap_err().contains("'lots' is not a size"));
        assert!(bytes("3 parsecs").unwrap_err().contains("unknown unit 'parsecs'"));
        assert!(bytes("-1GiB").is_err());
    }
}
