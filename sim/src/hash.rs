//! FNV-1a, 128-bit: a tiny stable hash for build-cache keys.
//!
//! Not cryptographic; it only has to tell different build inputs apart
//! and never change between releases, which a std `Hasher` does not promise.

const OFFSET: u128 = 0x6c62272e_07bb0142_62b82175_6295c58d;
const PRIME: u128 = 0x00000000_01000000_00000000_0000013b;

/// Incremental FNV-1a 128 hasher.
#[derive(Clone, Debug)]
pub struct Fnv128(u128);

impl Default for Fnv128 {
    fn default() -> Self {
        Fnv128(OFFSET)
    }
}

impl Fnv128 {
    /// A fresh hasher.
    pub fn new() -> Fnv128 {
        Fnv128::default()
    }

    /// Feeds raw bytes.
    pub fn bytes(&mut self, data: &[u8]) -> &mut Self {
        for &b in data {
            self.0 = (self.0 ^ b as u128).wrapping_mul(PRIME);
        }
        self
    }

    /// Feeds one item, length-prefixed so that ("ab","c") and ("a","bc")
    /// hash differently.
    pub fn item(&mut self, data: &[u8]) -> &mut Self {
        self.bytes(&(data.len() as u64).to_le_bytes()).bytes(data)
    }

    /// The digest.
    pub fn finish(&self) -> u128 {
        self.0
    }

    /// The digest as 32 lowercase hex digits.
    pub fn hex(&self) -> String {
        format!("{:032x}", self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_published_fnv1a_128_values() {
        assert_eq!(Fnv128::new().finish(), OFFSET);
        assert_eq!(
            Fnv128::new().bytes(b"a").hex(),
            "d228cb696f1a8caf78912b704e4a8964"
        );
        assert_eq!(
            Fnv128::new().bytes(b"foobar").hex(),
            "343e1662793c64bf6f0d3597ba446f18"
        );
    }

    #[test]
    fn items_are_framed() {
        let a = Fnv128::new().item(b"ab").item(b"c").finish();
        let b = Fnv128::new().item(b"a").item(b"bc").finish();
        assert_ne!(a, b);
    }
}
