//! Generational handles: a stale or foreign handle is an error, never a dangling object.
//! (The C API's handles are these numbers.)
//!
//! A handle is 64 bits: slot index (24), generation (20), object kind (4), context tag (16).
//! Destroying an object bumps its slot's generation, so old handles to the slot stop matching;
//! the tag is different for each live context (until 65 535 contexts were made), so a handle
//! from another context is recognised as such. 0 is never issued: it is the NULL handle.

use crate::{Error, Result};
use std::sync::atomic::{AtomicU32, Ordering};

const INDEX_BITS: u32 = 24;
const GENERATION_BITS: u32 = 20;
const KIND_BITS: u32 = 4;
const TAG_BITS: u32 = 16;
const GENERATION_LIMIT: u32 = 1 << GENERATION_BITS;
const INDEX_MASK: u64 = (1 << INDEX_BITS) - 1;
const GENERATION_MASK: u64 = (1 << GENERATION_BITS) - 1;
const KIND_MASK: u64 = (1 << KIND_BITS) - 1;
const TAG_MASK: u64 = (1 << TAG_BITS) - 1;
const GENERATION_SHIFT: u32 = INDEX_BITS;
const KIND_SHIFT: u32 = GENERATION_SHIFT + GENERATION_BITS;
const TAG_SHIFT: u32 = KIND_SHIFT + KIND_BITS;

/// Most live objects of one kind (meshes, textures, materials or frames) in one context.
pub const MAX_OBJECTS: u32 = 1 << INDEX_BITS;

/// A fresh context tag, never 0.
pub fn next_context_tag() -> u16 {
    static NEXT: AtomicU32 = AtomicU32::new(1);
    loop {
        let tag = NEXT.fetch_add(1, Ordering::Relaxed) & 0xffff;
        if let Ok(tag) = u16::try_from(tag) {
            if tag != 0 {
                return tag;
            }
        }
    }
}

/// Which object a handle names, so a mesh handle passed as a material is caught.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Mesh = 1,
    Texture = 2,
    Material = 3,
    Frame = 4,
}

impl Kind {
    pub fn name(self) -> &'static str {
        match self {
            Kind::Mesh => "mesh",
            Kind::Texture => "texture",
            Kind::Material => "material",
            Kind::Frame => "frame",
        }
    }

    fn from_bits(bits: u64) -> Option<Self> {
        [Kind::Mesh, Kind::Texture, Kind::Material, Kind::Frame]
            .into_iter()
            .find(|k| *k as u64 == bits)
    }
}

struct Slot<T> {
    generation: u32,
    value: Option<T>,
}

/// The live objects of one kind in one context.
pub struct Slots<T> {
    kind: Kind,
    tag: u16,
    slots: Vec<Slot<T>>,
    free: Vec<u32>,
}

impl<T> Slots<T> {
    pub fn new(kind: Kind, tag: u16) -> Self {
        Self {
            kind,
            tag,
            slots: Vec::new(),
            free: Vec::new(),
        }
    }

    /// Stores `value` and returns its handle.
    pub fn insert(&mut self, value: T) -> Result<u64> {
        let index = match self.free.pop() {
            Some(i) => i,
            None => {
                if self.slots.len() >= 1 << INDEX_BITS {
                    return Err(Error::TooLarge(format!(
                        "a context holds at most TRANSLUCID_MAX_OBJECTS ({MAX_OBJECTS}) {} \
                         objects",
                        self.kind.name()
                    )));
                }
                self.slots.push(Slot {
                    generation: 1,
                    value: None,
                });
                u32::try_from(self.slots.len() - 1).unwrap_or(u32::MAX)
            }
        };
        let slot = &mut self.slots[index as usize];
        slot.value = Some(value);
        let generation = slot.generation;
        Ok(self.encode(index, generation))
    }

    pub fn get(&self, handle: u64) -> Result<&T> {
        let index = self.check(handle)?;
        self.slots[index]
            .value
            .as_ref()
            .ok_or_else(|| self.stale(handle))
    }

    pub fn get_mut(&mut self, handle: u64) -> Result<&mut T> {
        let index = self.check(handle)?;
        let stale = self.stale(handle);
        self.slots[index].value.as_mut().ok_or(stale)
    }

    /// The live objects' handles and values, in slot order.
    pub fn iter(&self) -> impl Iterator<Item = (u64, &T)> {
        self.slots.iter().enumerate().filter_map(|(i, s)| {
            let index = u32::try_from(i).ok()?;
            Some((self.encode(index, s.generation), s.value.as_ref()?))
        })
    }

    /// Removes the object, so its handle becomes stale.
    pub fn remove(&mut self, handle: u64) -> Result<T> {
        let index = self.check(handle)?;
        let stale = self.stale(handle);
        let slot = &mut self.slots[index];
        let value = slot.value.take().ok_or(stale)?;
        // Skip 0 on wrap-around so that no issued handle is ever 0.
        slot.generation = (slot.generation + 1) % GENERATION_LIMIT;
        if slot.generation == 0 {
            slot.generation = 1;
        }
        self.free.push(u32::try_from(index).unwrap_or(u32::MAX));
        Ok(value)
    }

    pub fn live(&self) -> usize {
        self.slots.iter().filter(|s| s.value.is_some()).count()
    }

    fn encode(&self, index: u32, generation: u32) -> u64 {
        u64::from(index)
            | u64::from(generation) << GENERATION_SHIFT
            | (self.kind as u64) << KIND_SHIFT
            | u64::from(self.tag) << TAG_SHIFT
    }

    /// The slot index of a handle issued here whose object is still alive; a handle issued
    /// here whose object was destroyed is stale.
    fn check(&self, handle: u64) -> Result<usize> {
        let what = self.kind.name();
        let invalid = Error::InvalidHandle;
        if handle == 0 {
            return Err(invalid(format!("the {what} handle is NULL (0)")));
        }
        let tag = (handle >> TAG_SHIFT) & TAG_MASK;
        let kind = Kind::from_bits((handle >> KIND_SHIFT) & KIND_MASK);
        // Tag 0 is never issued, so such a value is garbage rather than foreign.
        if kind.is_some() && tag != 0 && tag != u64::from(self.tag) {
            return Err(Error::ForeignHandle(format!(
                "{what} handle {handle:#x} belongs to another context"
            )));
        }
        match kind {
            Some(k) if k == self.kind => {}
            Some(k) => {
                return Err(invalid(format!(
                    "handle {handle:#x} is a {} handle, not a {what} handle",
                    k.name()
                )))
            }
            None => return Err(invalid(format!("{handle:#x} is not a {what} handle"))),
        }
        let index = usize::try_from(handle & INDEX_MASK).unwrap_or(usize::MAX);
        let generation = (handle >> GENERATION_SHIFT) & GENERATION_MASK;
        match self.slots.get(index) {
            Some(slot) if generation == u64::from(slot.generation) && slot.value.is_some() => {
                Ok(index)
            }
            // Generations only grow (until they wrap, after a million reuses of one slot).
            Some(slot) if generation != 0 && generation <= u64::from(slot.generation) => {
                Err(self.stale(handle))
            }
            _ => Err(invalid(format!(
                "{what} handle {handle:#x} was never issued by this context"
            ))),
        }
    }

    fn stale(&self, handle: u64) -> Error {
        let what = self.kind.name();
        Error::StaleHandle(format!(
            "{what} handle {handle:#x} names a destroyed {what}"
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kind of error, by variant.
    fn kind<T>(r: Result<T>) -> &'static str {
        match r {
            Ok(_) => "ok",
            Err(Error::InvalidHandle(_)) => "invalid",
            Err(Error::StaleHandle(_)) => "stale",
            Err(Error::ForeignHandle(_)) => "foreign",
            Err(_) => "other",
        }
    }

    #[test]
    fn stale_foreign_and_wrong_kind_handles_are_told_apart() {
        let mut meshes = Slots::new(Kind::Mesh, 7);
        let mut other = Slots::new(Kind::Mesh, 8);
        let materials: Slots<()> = Slots::new(Kind::Material, 7);
        let a = meshes.insert("a").expect("insert");
        assert_eq!(*meshes.get(a).expect("live"), "a");
        let foreign = other.insert("x").expect("insert");
        assert_eq!(kind(meshes.get(foreign)), "foreign");
        assert_eq!(kind(materials.get(a)), "invalid");
        assert_eq!(kind(meshes.get(0)), "invalid");
        assert_eq!(meshes.remove(a).expect("remove"), "a");
        assert_eq!(kind(meshes.get(a)), "stale");
        // The slot is reused with a new generation: the old handle stays stale.
        let b = meshes.insert("b").expect("insert");
        assert_ne!(a, b);
        assert_eq!(kind(meshes.get(a)), "stale");
        assert_eq!(kind(meshes.get(b + (1 << GENERATION_SHIFT))), "invalid");
        assert_eq!(meshes.live(), 1);
    }

    #[test]
    fn a_slot_reused_a_million_times_never_issues_handle_zero_or_an_old_one() {
        let mut slots = Slots::new(Kind::Frame, 1);
        let first = slots.insert(0).expect("insert");
        slots.remove(first).expect("remove");
        let mut seen = std::collections::HashSet::new();
        for i in 0..GENERATION_LIMIT + 2 {
            let h = slots.insert(i).expect("insert");
            assert_ne!(
                h & (GENERATION_MASK << GENERATION_SHIFT),
                0,
                "generation 0 issued"
            );
            if i < GENERATION_LIMIT - 2 {
                assert!(seen.insert(h), "handle {h:#x} issued twice before the wrap");
            }
            slots.remove(h).expect("remove");
        }
        assert_eq!(slots.live(), 0);
    }
}
