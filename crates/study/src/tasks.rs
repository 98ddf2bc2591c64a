//! A study cut into tasks for a batch scheduler (Slurm job arrays): each task runs its
//! cases in order in one process; the tasks of a wave run at once, each wave after the
//! previous one has ended. A continuation chain (cases that continue from each other's
//! solutions) is one task, so that its cases run in order; every other case is a task of
//! its own. A task's wave is one after the waves of the tasks its cases continue from.

use crate::spec::Case;

/// One task: indices of its cases in the study, in the order they run.
pub type Task = Vec<usize>;

/// The waves of tasks of `cases` (sources before dependants, as in a study), restricted to
/// the cases selected by `selected`; tasks keep the study's order within a wave.
pub fn plan(cases: &[Case], selected: &dyn Fn(usize) -> bool) -> Vec<Vec<Task>> {
    // chain representative of each case: a continuation case joins the chain of the first
    // continuation case it continues from
    let mut root: Vec<usize> = (0..cases.len()).collect();
    for (j, c) in cases.iter().enumerate() {
        if !c.guess.is_continuation() {
            continue;
        }
        if let Some(&s) = c
            .sources
            .iter()
            .find(|&&s| cases[s].guess.is_continuation())
        {
            root[j] = root[s];
        }
    }
    // wave of each chain: one after the latest wave of any source outside the chain
    let mut wave = vec![0usize; cases.len()];
    for (j, c) in cases.iter().enumerate() {
        let w = c
            .sources
            .iter()
            .filter(|&&s| root[s] != root[j])
            .map(|&s| wave[root[s]] + 1)
            .max()
            .unwrap_or(0);
        let r = root[j];
        wave[r] = wave[r].max(w);
    }
    let mut waves: Vec<Vec<Task>> = Vec::new();
    let mut task_of_root: Vec<Option<(usize, usize)>> = vec![None; cases.len()];
    for j in (0..cases.len()).filter(|&j| selected(j)) {
        let r = root[j];
        match task_of_root[r] {
            Some((w, t)) => waves[w][t].push(j),
            None => {
                let w = wave[r];
                if waves.len() <= w {
                    waves.resize(w + 1, Vec::new());
                }
                waves[w].push(vec![j]);
                task_of_root[r] = Some((w, waves[w].len() - 1));
            }
        }
    }
    waves.retain(|w| !w.is_empty());
    waves
}
