//! The one spelling of each value of the renderer's option enums ([`Method`],
//! [`Normals`], [`AntiAliasingKind`], [`Interpolation`](super::polygon::Interpolation)),
//! shared by their `FromStr` (through [`crate::spelling`]'s one parser) and `Display`: the command line parses the library's
//! enums through `FromStr`, a viewer's query the same, and the scene files' serde
//! spellings are checked against the same names (each enum's tests), so a value is
//! written one way everywhere.
//!
//! [`Method`]: super::Method
//! [`Normals`]: super::Normals
//! [`AntiAliasingKind`]: super::AntiAliasingKind

#[cfg(test)]
mod tests {
    use crate::render::{AntiAliasingKind, Method, Normals, polygon::Interpolation};

    /// `Display`'s spelling read back by `FromStr`, for every value.
    fn round_trip<T>(all: &[T])
    where
        T: Copy + std::fmt::Debug + PartialEq + std::fmt::Display + std::str::FromStr,
        <T as std::str::FromStr>::Err: std::fmt::Debug,
    {
        for &v in all {
            assert_eq!(v.to_string().parse::<T>().unwrap(), v);
        }
        assert!("not-a-value".parse::<T>().is_err());
    }

    /// Serde (a scene file) reads `Display`'s spelling as the same value, for every
    /// value: one spelling set an enum.
    fn serde_agrees<T>(all: &[T])
    where
        T: Copy + std::fmt::Debug + PartialEq + std::fmt::Display + serde::de::DeserializeOwned,
    {
        #[derive(serde::Deserialize)]
        struct Holder<T> {
            v: T,
        }
        for &v in all {
            let read: Holder<T> = toml::from_str(&format!("v = \"{v}\"")).unwrap();
            assert_eq!(read.v, v, "{v}");
        }
    }

    #[test]
    fn every_enum_reads_back_its_own_spelling_by_from_str_and_serde() {
        round_trip(&Normals::ALL);
        round_trip(&AntiAliasingKind::ALL);
        round_trip(&Method::ALL);
        round_trip(&Interpolation::ALL);
        serde_agrees(&Normals::ALL);
        serde_agrees(&AntiAliasingKind::ALL);
        assert_eq!(Method::ALL.map(Method::name), ["trace", "front-to-back", "painter", "zbuffer", "scanline"]);
    }
}
