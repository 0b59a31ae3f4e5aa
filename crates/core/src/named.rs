//! Values chosen by name on the command line, in scene files and in
//! sidecars (render modes, prefilters, back-to-front orders, shadow
//! methods, layer effects, deformations): one rule reads a name and writes
//! it, and one error lists every name. A type lists its values in an
//! inherent `ALL` array and names each with an inherent `name`;
//! [`crate::by_name!`] makes it [`Named`], `FromStr` and `Display` from them.

/// A value chosen by its name.
pub trait Named: Copy + 'static {
    /// What a value is, in an error: "mode", "prefilter".
    const WHAT: &'static str;
    /// Every value, in the order an error lists their names.
    fn all() -> &'static [Self];
    fn name(self) -> &'static str;
}

/// The value named `text`, or an error that lists every name.
pub fn parse<T: Named>(text: &str) -> Result<T, String> {
    T::all().iter().copied().find(|v| v.name() == text).ok_or_else(|| {
        let names: Vec<&str> = T::all().iter().map(|v| v.name()).collect();
        format!("unknown {} '{text}'; available: {}", T::WHAT, names.join(", "))
    })
}

/// [`Named`], `FromStr` and `Display` for `$ty`, a value called `$what` in
/// errors, from its inherent `ALL` and `name`.
#[macro_export]
macro_rules! by_name {
    ($ty:ty, $what:literal) => {
        impl $crate::named::Named for $ty {
            const WHAT: &'static str = $what;
            fn all() -> &'static [Self] {
                &<$ty>::ALL
            }
            fn name(self) -> &'static str {
                <$ty>::name(self)
            }
        }
        impl std::str::FromStr for $ty {
            type Err = String;
            fn from_str(text: &str) -> Result<Self, String> {
                $crate::named::parse(text)
            }
        }
        impl std::fmt::Display for $ty {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(<$ty>::name(*self))
            }
        }
    };
}

#[cfg(test)]
mod tests {
    #[derive(Debug, Clone, Copy, PartialEq)]
    enum Fruit {
        Apple,
        Pear,
    }

    impl Fruit {
        const ALL: [Fruit; 2] = [Fruit::Apple, Fruit::Pear];
        fn name(self) -> &'static str {
            match self {
                Fruit::Apple => "apple",
                Fruit::Pear => "pear",
            }
        }
    }

    crate::by_name!(Fruit, "fruit");

    #[test]
    fn a_name_reads_its_value_and_writes_back_and_an_unknown_one_lists_them_all() {
        for fruit in Fruit::ALL {
            assert_eq!(fruit.to_string().parse::<Fruit>(), Ok(fruit));
        }
        assert_eq!("plum".parse::<Fruit>(), Err("unknown fruit 'plum'; available: apple, pear".to_string()));
    }
}
