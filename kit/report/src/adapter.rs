//! The adapter a run was made on, as reports name it.

use serde::{Deserialize, Serialize};

/// What the report says about an adapter.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq, Eq)]
pub struct AdapterDescription {
    pub name: String,
    pub backend: String,
    pub driver: String,
    pub driver_info: String,
    pub device_type: String,
}

impl AdapterDescription {
    /// A file-name-safe identifier, used to keep one adapter's snapshots from judging another's.
    pub fn slug(&self) -> String {
        let raw = format!("{}-{}", self.backend, self.name);
        let mut slug = String::with_capacity(raw.len());
        for c in raw.chars() {
            if c.is_ascii_alphanumeric() {
                slug.push(c.to_ascii_lowercase());
            } else if !slug.ends_with('_') {
                slug.push('_');
            }
        }
        slug.trim_matches('_').to_owned()
    }
}
