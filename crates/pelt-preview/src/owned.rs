//! State a feature owns, kept by the renderer's core without knowing its type: per-view
//! targets (the OIT accumulation, the scene colour) in [`crate::targets::ViewTargets`],
//! per-scene state (the distance maps) in [`crate::scene_view::SceneView`]. The core stores
//! and hands it back; only the feature that made it reads it, by type. A pass that looks for
//! state its view lacks gets a [`crate::draw::MissingInput`], never a silent skip.

use std::any::Any;

use crate::draw::MissingInput;

/// Values of distinct types, one of each at most.
#[derive(Default)]
pub struct Owned {
    items: Vec<Box<dyn Any + Send + Sync>>,
}

impl std::fmt::Debug for Owned {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Owned({} items)", self.items.len())
    }
}

impl Owned {
    /// Holds `value`, replacing the one of its type.
    pub fn insert<T: Any + Send + Sync>(&mut self, value: T) {
        self.remove::<T>();
        self.items.push(Box::new(value));
    }

    /// Drops the value of type `T`, if held.
    pub fn remove<T: Any>(&mut self) {
        self.items.retain(|i| !i.is::<T>());
    }

    /// The value of type `T`, if held.
    pub fn get<T: Any>(&self) -> Option<&T> {
        self.items.iter().find_map(|i| i.downcast_ref())
    }

    /// The value of type `T`, mutably, if held.
    pub fn get_mut<T: Any>(&mut self) -> Option<&mut T> {
        self.items.iter_mut().find_map(|i| i.downcast_mut())
    }

    /// The value of type `T`, or the error `pass` reports when the view lacks `what`.
    pub fn need<T: Any>(&self, pass: &'static str, what: &str) -> Result<&T, MissingInput> {
        self.get().ok_or_else(|| MissingInput {
            pass,
            what: what.to_owned(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_value_per_type_found_by_type() {
        let mut o = Owned::default();
        o.insert(3_u32);
        o.insert("a");
        o.insert(5_u32);
        assert_eq!(o.get::<u32>(), Some(&5));
        assert_eq!(o.get::<&str>(), Some(&"a"));
        assert!(o.get::<f32>().is_none());
        let e = o
            .need::<f32>("wboit composite", "the OIT targets")
            .unwrap_err();
        assert!(e.to_string().contains("the OIT targets"), "{e}");
        o.remove::<u32>();
        assert!(o.get::<u32>().is_none());
    }
}
