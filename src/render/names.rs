//! The one spelling of each value of the renderer's option enums ([`Method`],
//! [`Normals`], [`AntiAliasingKind`], [`Interpolation`](super::polygon::Interpolation)),
//! shared by their `FromStr` and `Display`: the command line parses the library's
//! enums through `FromStr`, a viewer's query the same, and the scene files' serde
//! spellings are checked against the same names (each enum's tests), so a value is
//! written one way everywhere.
//!
//! [`Method`]: super::Method
//! [`Normals`]: super::Normals
//! [`AntiAliasingKind`]: super::AntiAliasingKind

/// The value of `all` whose `name` is `s` (exactly), else a message listing the names:
/// `"x" is not a, b or c`.
pub(crate) fn parse_name<T: Copy>(s: &str, all: &[T], name: fn(T) -> &'static str) -> Result<T, String> {
    all.iter().copied().find(|&v| name(v) == s).ok_or_else(|| {
        let names: Vec<&str> = all.iter().map(|&v| name(v)).collect();
        let list = match names.split_last() {
            Some((last, [])) => (*last).to_owned(),
            Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
            None => String::new(),
        };
        format!("{s:?} is not {list}")
    })
}

#[cfg(test)]
mod tests {
    use super::parse_name;
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

    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Fruit {
        Apple,
        Pear,
        Plum,
    }

    fn name(f: Fruit) -> &'static str {
        match f {
            Fruit::Apple => "apple",
            Fruit::Pear => "pear",
            Fruit::Plum => "plum",
        }
    }

    #[test]
    fn a_name_gives_its_value_and_anything_else_the_list() {
        let all = [Fruit::Apple, Fruit::Pear, Fruit::Plum];
        assert_eq!(parse_name("pear", &all, name), Ok(Fruit::Pear));
        assert_eq!(parse_name("Pear", &all, name), Err("\"Pear\" is not apple, pear or plum".to_owned()));
        assert_eq!(parse_name("fig", &all[..1], name), Err("\"fig\" is not apple".to_owned()));
    }
}
