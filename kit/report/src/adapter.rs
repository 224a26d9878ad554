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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slug_is_backend_and_name_lowercased_with_one_underscore_for_each_run_of_other_characters() {
        let adapter = AdapterDescription {
            name: "llvmpipe (LLVM 15.0.6, 256 bits)".into(),
            backend: "vulkan".into(),
            ..Default::default()
        };
        assert_eq!(adapter.slug(), "vulkan_llvmpipe_llvm_15_0_6_256_bits");
    }
}
