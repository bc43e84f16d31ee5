//! Enums with one spelling a value: the parser every such enum's `FromStr` shares
//! (the renderer's options, [`SetOp`](crate::octree::SetOp)), so the command line, a
//! viewer's query and a scene file read a value the same way and a wrong one is told
//! the same way, with the list of the names there are.

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

/// `FromStr` by [`parse_name`] over the enum's `ALL` and `name`, and `Display` as its
/// `name`: the two impls every enum of one spelling shares, written once.
macro_rules! spelled {
    ($t:ty) => {
        impl std::str::FromStr for $t {
            type Err = String;

            /// Parses the value's `name`, exactly.
            fn from_str(s: &str) -> std::result::Result<Self, String> {
                crate::spelling::parse_name(s, &<$t>::ALL, <$t>::name)
            }
        }

        impl std::fmt::Display for $t {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.name())
            }
        }
    };
}
pub(crate) use spelled;

#[cfg(test)]
mod tests {
    use super::parse_name;

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
