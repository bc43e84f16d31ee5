//! Memory budgets: jobs whose estimated memory exceeds the budget are refused before
//! they start, naming the estimate.

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

    /// Fails with [`Error::OverBudget`] when `estimate` exceeds the budget.
    pub fn check(&self, job: impl Into<String>, estimate: u64) -> Result<()> {
        if estimate > self.0 {
            return Err(Error::OverBudget { job: job.into(), estimate, budget: self.0 });
        }
        Ok(())
    }
}

impl Default for MemoryBudget {
    fn default() -> Self {
        MemoryBudget::half_of_ram()
    }
}
