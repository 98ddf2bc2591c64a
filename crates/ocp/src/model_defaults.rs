//! A model's defaults of the gait problem (the `[problem]` table of its settings file),
//! layered under the problem keys of a prediction file or study file. Precedence: built-in
//! defaults < model settings < prediction or study file < command-line option.

use crate::settings::ProblemSettings;
use std::path::Path;
use stride_model::model_settings::ModelSettings;
use toml::{Table, Value};

/// A model's problem defaults, each key checked.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ModelProblemDefaults {
    /// The `[problem]` table of the model's settings file (keys of [`ProblemSettings`]).
    pub table: Table,
}

/// A `[problem]` key of a model settings file that is unknown or out of range.
#[derive(Debug, thiserror::Error)]
#[error("{file}:{line}: `problem.{key}`: {message}")]
pub struct ModelDefaultsError {
    /// The settings file.
    pub file: String,
    /// Line of the key (1-based).
    pub line: usize,
    /// The top-level problem key.
    pub key: String,
    /// What is wrong.
    pub message: String,
}

impl ModelProblemDefaults {
    /// The checked `[problem]` table of `settings`, read from `file`: each key alone must
    /// give valid problem settings.
    pub fn new(settings: &ModelSettings, file: &str) -> Result<Self, ModelDefaultsError> {
        for (key, value) in &settings.problem {
            let fail = |message: String| ModelDefaultsError {
                file: file.into(),
                line: settings.problem_lines.get(key).copied().unwrap_or(1),
                key: key.clone(),
                message,
            };
            let one = Table::from_iter([(key.clone(), value.clone())]);
            let s: ProblemSettings = Value::Table(one)
                .try_into()
                .map_err(|e: toml::de::Error| fail(e.message().trim().replace('\n', " ")))?;
            s.validate().map_err(|e| fail(e.to_string()))?;
        }
        Ok(Self {
            table: settings.problem.clone(),
        })
    }

    /// The defaults of the model named by `model` (an `.osim` file or a shipped model's
    /// name; `None`: the built-in model), from `explicit` or the model's own settings file
    /// ([`ModelSettings::of_named_model`]).
    pub fn of_named_model(
        model: Option<&Path>,
        explicit: Option<&Path>,
    ) -> Result<Self, Box<dyn std::error::Error + Send + Sync>> {
        let (settings, file) = ModelSettings::of_named_model(model, explicit)?;
        Ok(Self::new(&settings, &file)?)
    }

    /// `over` (a prediction file's `[problem]`, a study's `[base]`) merged on top of the
    /// defaults.
    pub fn under(&self, over: &Table) -> Table {
        let mut t = self.table.clone();
        merge_tables(&mut t, over);
        t
    }

    /// The problem settings of `over` on top of the defaults (not yet validated).
    pub fn settings(&self, over: &Table) -> Result<ProblemSettings, toml::de::Error> {
        Value::Table(self.under(over)).try_into()
    }
}

/// Deep-merge `over` into `base`: tables merge key by key, anything else replaces.
pub fn merge_tables(base: &mut Table, over: &Table) {
    for (k, v) in over {
        match (base.get_mut(k), v) {
            (Some(Value::Table(b)), Value::Table(o)) => merge_tables(b, o),
            _ => {
                base.insert(k.clone(), v.clone());
            }
        }
    }
}
