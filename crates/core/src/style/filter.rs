//! Attribute filters: which points a view shows, by any attribute the file
//! has (`--filter NAME=MIN..MAX`, `--filter NAME=V1,V2,...`, by the names
//! `info` lists) and by return (`--returns first|last|only|N`, over
//! return_number and number_of_returns). All filters must hold. They are
//! part of the [`super::Style`], applied to each cloud (a whole file, or each
//! streamed frame's nodes) before the scene is flattened, so every mode, the
//! reference, picks and measures see the same points.

use std::str::FromStr;

use crate::cloud::PointCloud;
use crate::cloud::attributes::{Attributes, names};

/// What one attribute must be.
#[derive(Debug, Clone, PartialEq)]
pub enum Test {
    /// MIN..MAX, both ends kept.
    Range(f64, f64),
    /// One of these values.
    Values(Vec<f64>),
}

/// An attribute and what it must be.
#[derive(Debug, Clone, PartialEq)]
pub struct Filter {
    pub name: String,
    pub test: Test,
}

/// The return shorthand.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Returns {
    /// return_number = 1.
    First,
    /// return_number = number_of_returns.
    Last,
    /// number_of_returns = 1.
    Only,
    /// return_number = N.
    Number(u8),
}

impl FromStr for Filter {
    type Err = String;
    fn from_str(text: &str) -> Result<Self, String> {
        let bad = |why: &str| format!("'{text}' is not a filter NAME=MIN..MAX or NAME=V1,V2,...: {why}");
        let (name, test) = text.split_once('=').ok_or_else(|| bad("no '='"))?;
        let name = name.trim();
        if name.is_empty() {
            return Err(bad("no attribute name"));
        }
        let number = |v: &str| v.trim().parse::<f64>().ok().filter(|v| !v.is_nan());
        let test = if let Some((lo, hi)) = test.split_once("..") {
            let (lo, hi) = (
                number(lo).ok_or_else(|| bad("MIN is not a number"))?,
                number(hi).ok_or_else(|| bad("MAX is not a number"))?,
            );
            if lo > hi {
                return Err(bad("MIN is above MAX"));
            }
            Test::Range(lo, hi)
        } else {
            let values: Option<Vec<f64>> = test.split(',').map(number).collect();
            Test::Values(values.filter(|v| !v.is_empty()).ok_or_else(|| bad("a value is not a number"))?)
        };
        Ok(Filter { name: name.to_string(), test })
    }
}

impl Filter {
    /// Its text form, as the flag takes it.
    pub fn text(&self) -> String {
        match &self.test {
            Test::Range(lo, hi) => format!("{}={lo}..{hi}", self.name),
            Test::Values(values) => {
                let values: Vec<String> = values.iter().map(f64::to_string).collect();
                format!("{}={}", self.name, values.join(","))
            }
        }
    }

    fn holds(&self, value: f64) -> bool {
        match &self.test {
            Test::Range(lo, hi) => (*lo..=*hi).contains(&value),
            Test::Values(values) => values.contains(&value),
        }
    }
}

impl FromStr for Returns {
    type Err = String;
    fn from_str(text: &str) -> Result<Self, String> {
        match text {
            "first" => Ok(Returns::First),
            "last" => Ok(Returns::Last),
            "only" => Ok(Returns::Only),
            _ => text
                .parse::<u8>()
                .ok()
                .filter(|n| *n >= 1)
                .map(Returns::Number)
                .ok_or_else(|| format!("'{text}' is not a return: use first, last, only or a number from 1")),
        }
    }
}

impl Returns {
    pub fn text(self) -> String {
        match self {
            Returns::First => "first".into(),
            Returns::Last => "last".into(),
            Returns::Only => "only".into(),
            Returns::Number(n) => n.to_string(),
        }
    }
}

/// The points of `cloud` of the `classes` shown (all when `None`) that every
/// filter and the return shorthand keep, or an error naming an attribute the
/// cloud lacks.
pub fn kept(
    cloud: &PointCloud,
    classes: Option<&[u8]>,
    filters: &[Filter],
    returns: Option<Returns>,
) -> Result<Vec<u32>, String> {
    kept_of(&cloud.attributes, cloud.len(), classes, filters, returns)
}

/// [`kept`] over `n` points' `attributes` (a cloud's, or a file's records').
pub fn kept_of(
    attributes: &Attributes,
    n: usize,
    classes: Option<&[u8]>,
    filters: &[Filter],
    returns: Option<Returns>,
) -> Result<Vec<u32>, String> {
    let column = |name: &str, wanted_by: &str| super::column_of(attributes, name, wanted_by);
    let mut keep = vec![true; n];
    if let Some(shown) = classes {
        let class = column(names::CLASSIFICATION, "--classes")?;
        keep.iter_mut().enumerate().for_each(|(i, k)| *k = shown.contains(&(class.get(i) as u8)));
    }
    for filter in filters {
        let values = column(&filter.name, "--filter")?;
        keep.iter_mut().enumerate().for_each(|(i, k)| *k = *k && filter.holds(values.get(i)));
    }
    if let Some(returns) = returns {
        let number = column(names::RETURN_NUMBER, "--returns")?;
        let count = column(names::NUMBER_OF_RETURNS, "--returns")?;
        for (i, k) in keep.iter_mut().enumerate() {
            let (r, n) = (number.get(i), count.get(i));
            *k = *k
                && match returns {
                    Returns::First => r == 1.0,
                    Returns::Last => r == n,
                    Returns::Only => n == 1.0,
                    Returns::Number(want) => r == f64::from(want),
                };
        }
    }
    Ok((0..n as u32).filter(|&i| keep[i as usize]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::Values;

    #[test]
    fn filters_read_their_text_and_keep_what_holds() {
        let n = 12;
        let mut cloud = PointCloud::facing_z(vec![glam::Vec3::ZERO; n], 0.1, [0; 3]);
        cloud.attributes.push("intensity", Values::U16((0..n as u16).map(|i| i * 10).collect()));
        cloud.attributes.push(names::RETURN_NUMBER, Values::U8((0..n).map(|i| (i % 3 + 1) as u8).collect()));
        cloud.attributes.push(names::NUMBER_OF_RETURNS, Values::U8(vec![3; n]));
        let range: Filter = "intensity=20..50".parse().unwrap();
        assert_eq!(range.test, Test::Range(20.0, 50.0));
        assert_eq!(kept(&cloud, None, std::slice::from_ref(&range), None).unwrap(), vec![2, 3, 4, 5]);
        assert_eq!(kept(&cloud, None, &[range], Some(Returns::First)).unwrap(), vec![3]);
        let values: Filter = "intensity=0,110".parse().unwrap();
        assert_eq!(kept(&cloud, None, &[values], Some(Returns::Last)).unwrap(), vec![11]);
        assert_eq!(kept(&cloud, None, &[], Some(Returns::Number(2))).unwrap(), vec![1, 4, 7, 10]);
        assert!(kept(&cloud, None, &[], Some(Returns::Only)).unwrap().is_empty());
        let missing = kept(&cloud, None, &["gps_time=0..1".parse().unwrap()], None).unwrap_err();
        assert!(missing.contains("gps_time") && missing.contains("intensity"), "{missing}");
        for bad in ["intensity", "=1..2", "intensity=a..2", "intensity=3..2", "intensity=1,x", "intensity="] {
            assert!(bad.parse::<Filter>().is_err(), "{bad}");
        }
        assert!("0".parse::<Returns>().is_err() && "firsts".parse::<Returns>().is_err());
        assert_eq!("intensity=20..50".parse::<Filter>().unwrap().text(), "intensity=20..50");
    }
}
