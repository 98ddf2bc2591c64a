//! Which settings file belongs to the model a prediction names, without importing the
//! model (the problem defaults are needed before the model is loaded).

use super::{ModelSettings, ModelSettingsError};
use crate::shipped::shipped;
use std::path::Path;

impl ModelSettings {
    /// The settings of the model named by `model` (an `.osim` file or a shipped model's
    /// name; `None`: the built-in model): `explicit` when given; else a shipped model's own
    /// (when no file of that name exists); else `<model>.toml` beside the `.osim`; else the
    /// defaults. Returns them with the name of their source, for messages.
    pub fn of_named_model(
        model: Option<&Path>,
        explicit: Option<&Path>,
    ) -> Result<(Self, String), ModelSettingsError> {
        if let Some(f) = explicit {
            return Ok((Self::read(f)?, f.display().to_string()));
        }
        let Some(path) = model else {
            return Ok((Self::default(), "default model settings".into()));
        };
        let bare = path.components().count() == 1 && path.extension().is_none();
        let named = path.to_str().filter(|_| bare && !path.exists());
        if let Some(s) = named.and_then(shipped) {
            let name = format!("{} (shipped settings of {})", s.file_name, s.name);
            return Ok((Self::parse(s.settings, &name)?, name));
        }
        match Self::beside(path) {
            Some(f) => Ok((Self::read(&f)?, f.display().to_string())),
            None => Ok((Self::default(), "default model settings".into())),
        }
    }
}
