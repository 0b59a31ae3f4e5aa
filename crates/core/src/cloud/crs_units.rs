//! The units a file's coordinates are in, from the CRS it declares: its
//! WKT (WKT1 or WKT2, a compound CRS's horizontal and vertical parts), else
//! its GeoTIFF keys (the projected, geographic and vertical CRS codes and
//! the linear-unit keys). Where neither names a unit but an EPSG code is
//! known, the code's PROJ definition gives it (`crs-definitions`, the EPSG
//! table as a crate: no network and no PROJ database needed).
//!
//! The WKT reader is hand-written: it only needs the tree's keywords, quoted
//! names and numbers, which no maintained crate reads for both WKT versions
//! without pulling in PROJ.

use std::fmt;

/// A length unit: its name and how many metres it is.
#[derive(Debug, Clone, PartialEq)]
pub struct Unit {
    pub name: String,
    /// Metres per unit (`None` for an angle: a geographic CRS's degrees).
    pub metres: Option<f64>,
}

/// Metres per US survey foot (1200/3937).
pub const US_SURVEY_FOOT: f64 = 1200.0 / 3937.0;
/// Metres per international foot.
pub const INTERNATIONAL_FOOT: f64 = 0.3048;

impl Unit {
    /// The unit of `metres` per unit, by its standard name where it has one.
    pub fn of_metres(metres: f64, name: &str) -> Unit {
        let close = |m: f64| (metres - m).abs() <= 1e-9 * m;
        let standard = if close(1.0) {
            "metre"
        } else if close(INTERNATIONAL_FOOT) {
            "international foot"
        } else if close(US_SURVEY_FOOT) {
            "US survey foot"
        } else {
            name
        };
        Unit { name: standard.to_string(), metres: Some(metres) }
    }

    fn degree() -> Unit {
        Unit { name: "degree".into(), metres: None }
    }
}

impl fmt::Display for Unit {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.metres {
            Some(m) if m != 1.0 => write!(f, "{} ({m} m)", self.name),
            _ => f.write_str(&self.name),
        }
    }
}

/// What a file's CRS says about its coordinates.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CrsUnits {
    /// The EPSG code of the CRS (a compound CRS's own, else its horizontal part's).
    pub epsg: Option<u32>,
    pub horizontal: Option<Unit>,
    pub vertical: Option<Unit>,
}

/// What is said where a file declares no CRS, or none whose units are known.
pub const UNITS_OF_THE_FILE: &str = "units of the file";

impl CrsUnits {
    /// The horizontal unit's name, or [`UNITS_OF_THE_FILE`].
    pub fn horizontal_name(&self) -> &str {
        self.horizontal.as_ref().map_or(UNITS_OF_THE_FILE, |u| u.name.as_str())
    }

    /// The vertical unit's name: its own, else the horizontal one's (a
    /// projected CRS without a vertical part), else [`UNITS_OF_THE_FILE`].
    pub fn vertical_name(&self) -> &str {
        match (&self.vertical, &self.horizontal) {
            (Some(v), _) => &v.name,
            (None, Some(h)) if h.metres.is_some() => &h.name,
            _ => UNITS_OF_THE_FILE,
        }
    }

    /// From a WKT text (WKT1 or WKT2).
    pub fn from_wkt(text: &str) -> CrsUnits {
        let Some(root) = wkt::parse(text) else { return CrsUnits::default() };
        let compound = matches!(root.keyword.as_str(), "COMPD_CS" | "COMPOUNDCRS");
        let (horizontal_crs, vertical_crs) = if compound {
            let horizontal = root.children().find(|c| !is_vertical(&c.keyword) && is_crs(&c.keyword));
            let vertical = root.children().find(|c| is_vertical(&c.keyword));
            (horizontal, vertical)
        } else if is_vertical(&root.keyword) {
            (None, Some(&root))
        } else {
            (Some(&root), None)
        };
        let epsg = root.epsg().or_else(|| horizontal_crs.and_then(wkt::Node::epsg));
        let mut units =
            CrsUnits { epsg, horizontal: horizontal_crs.and_then(crs_unit), vertical: vertical_crs.and_then(crs_unit) };
        if units.horizontal.is_none() {
            units.horizontal = horizontal_crs.and_then(wkt::Node::epsg).and_then(unit_of_code);
        }
        units
    }

    /// From GeoTIFF keys as (key id, value) pairs: ProjectedCRSGeoKey 3072,
    /// GeodeticCRSGeoKey 2048, VerticalCRSGeoKey 4096, ProjLinearUnitsGeoKey
    /// 3076 and VerticalUnitsGeoKey 4099.
    pub fn from_geotiff_keys(keys: &[(u16, u16)]) -> CrsUnits {
        let key = |id: u16| keys.iter().find(|(k, _)| *k == id).map(|(_, v)| *v).filter(|v| (1024..32767).contains(v));
        let (projected, geographic) = (key(3072), key(2048));
        let horizontal = key(3076)
            .and_then(unit_of_geotiff)
            .or_else(|| projected.and_then(|c| unit_of_code(c as u32)))
            .or_else(|| geographic.map(|_| Unit::degree()));
        let vertical = key(4099).and_then(unit_of_geotiff).or_else(|| key(4096).and_then(|c| unit_of_code(c as u32)));
        CrsUnits { epsg: projected.or(geographic).map(u32::from), horizontal, vertical }
    }
}

fn is_crs(keyword: &str) -> bool {
    keyword.ends_with("CS") || keyword.ends_with("CRS")
}

fn is_vertical(keyword: &str) -> bool {
    matches!(keyword, "VERT_CS" | "VERTCRS" | "VERTICALCRS")
}

/// A CRS node's unit: its own UNIT (WKT1) or LENGTHUNIT (WKT2), else the
/// first axis's; a geographic CRS's is the degree.
fn crs_unit(node: &wkt::Node) -> Option<Unit> {
    if matches!(node.keyword.as_str(), "GEOGCS" | "GEOGCRS" | "GEOGRAPHICCRS") {
        return Some(Unit::degree());
    }
    let own = node.children().find(|c| matches!(c.keyword.as_str(), "UNIT" | "LENGTHUNIT"));
    let axis = || {
        node.children().filter(|c| c.keyword == "AXIS").find_map(|a| a.children().find(|c| c.keyword == "LENGTHUNIT"))
    };
    let unit = own.or_else(axis)?;
    let name = unit.text(0).unwrap_or("unit");
    let metres = unit.number(1)?;
    (metres.is_finite() && metres > 0.0).then(|| Unit::of_metres(metres, name))
}

/// A GeoTIFF linear-units code (EPSG unit codes 9001 metre, 9002 foot, 9003 US survey foot).
fn unit_of_geotiff(code: u16) -> Option<Unit> {
    match code {
        9001 => Some(Unit::of_metres(1.0, "metre")),
        9002 => Some(Unit::of_metres(INTERNATIONAL_FOOT, "foot")),
        9003 => Some(Unit::of_metres(US_SURVEY_FOOT, "US survey foot")),
        _ => None,
    }
}

/// The unit of an EPSG CRS code, from its PROJ definition (`+units=`, `+to_meter=`, or degrees).
pub fn unit_of_code(code: u32) -> Option<Unit> {
    let def = crs_definitions::from_code(u16::try_from(code).ok()?)?;
    let proj4 = def.proj4;
    let value = |key: &str| proj4.split_whitespace().find_map(|part| part.strip_prefix(key));
    if let Some(to_meter) = value("+to_meter=").and_then(|v| v.parse::<f64>().ok()) {
        return Some(Unit::of_metres(to_meter, "unit"));
    }
    match value("+units=") {
        Some("m") => Some(Unit::of_metres(1.0, "metre")),
        Some("ft") => Some(Unit::of_metres(INTERNATIONAL_FOOT, "foot")),
        Some("us-ft") => Some(Unit::of_metres(US_SURVEY_FOOT, "US survey foot")),
        _ if proj4.contains("+proj=longlat") => Some(Unit::degree()),
        _ => None,
    }
}

mod wkt {
    //! A WKT tree: KEYWORD[item, item, ...], each item a quoted text, a
    //! number, a bare word or a node; nesting is bounded.

    pub struct Node {
        pub keyword: String,
        pub items: Vec<Item>,
    }

    pub enum Item {
        Text(String),
        Number(f64),
        Node(Node),
    }

    const MAX_DEPTH: usize = 64;

    impl Node {
        pub fn children(&self) -> impl Iterator<Item = &Node> {
            self.items.iter().filter_map(|i| if let Item::Node(n) = i { Some(n) } else { None })
        }

        pub fn text(&self, at: usize) -> Option<&str> {
            match self.items.get(at)? {
                Item::Text(t) => Some(t),
                _ => None,
            }
        }

        pub fn number(&self, at: usize) -> Option<f64> {
            match self.items.get(at)? {
                Item::Number(n) => Some(*n),
                Item::Text(t) => t.parse().ok(),
                Item::Node(_) => None,
            }
        }

        /// Its own `AUTHORITY["EPSG","code"]` (WKT1) or `ID["EPSG",code]` (WKT2).
        pub fn epsg(&self) -> Option<u32> {
            self.children()
                .filter(|c| matches!(c.keyword.as_str(), "AUTHORITY" | "ID"))
                .find(|c| c.text(0).is_some_and(|a| a.eq_ignore_ascii_case("EPSG")))
                .and_then(|c| c.number(1))
                .filter(|n| n.fract() == 0.0 && *n > 0.0 && *n < u32::MAX as f64)
                .map(|n| n as u32)
        }
    }

    /// The tree of `text`, or `None` when it is not WKT.
    pub fn parse(text: &str) -> Option<Node> {
        let mut reader = Reader { bytes: text.as_bytes(), at: 0 };
        reader.node(0)
    }

    struct Reader<'a> {
        bytes: &'a [u8],
        at: usize,
    }

    impl Reader<'_> {
        fn skip_space(&mut self) {
            while self.bytes.get(self.at).is_some_and(|b| b.is_ascii_whitespace()) {
                self.at += 1;
            }
        }

        fn word(&mut self) -> String {
            self.skip_space();
            let start = self.at;
            while self.bytes.get(self.at).is_some_and(|b| b.is_ascii_alphanumeric() || b"_.+-".contains(b)) {
                self.at += 1;
            }
            String::from_utf8_lossy(&self.bytes[start..self.at]).to_ascii_uppercase()
        }

        fn node(&mut self, depth: usize) -> Option<Node> {
            if depth > MAX_DEPTH {
                return None;
            }
            let keyword = self.word();
            self.skip_space();
            let open = *self.bytes.get(self.at)?;
            if keyword.is_empty() || (open != b'[' && open != b'(') {
                return None;
            }
            self.at += 1;
            let mut items = Vec::new();
            loop {
                self.skip_space();
                match *self.bytes.get(self.at)? {
                    b']' | b')' => {
                        self.at += 1;
                        return Some(Node { keyword, items });
                    }
                    b',' => self.at += 1,
                    b'"' => items.push(Item::Text(self.quoted()?)),
                    _ => {
                        let start = self.at;
                        let word = self.word();
                        self.skip_space();
                        if matches!(self.bytes.get(self.at), Some(b'[') | Some(b'(')) {
                            self.at = start;
                            items.push(Item::Node(self.node(depth + 1)?));
                        } else if word.is_empty() {
                            return None;
                        } else {
                            items.push(word.parse().map(Item::Number).unwrap_or(Item::Text(word)));
                        }
                    }
                }
            }
        }

        /// A quoted text; `""` inside stands for one quote.
        fn quoted(&mut self) -> Option<String> {
            self.at += 1;
            let mut out = Vec::new();
            loop {
                let b = *self.bytes.get(self.at)?;
                self.at += 1;
                if b == b'"' {
                    if self.bytes.get(self.at) == Some(&b'"') {
                        out.push(b'"');
                        self.at += 1;
                        continue;
                    }
                    return Some(String::from_utf8_lossy(&out).into_owned());
                }
                out.push(b);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const OREGON_FT: &str = r#"PROJCS["NAD83(HARN) / Oregon GIC Lambert (ft)",GEOGCS["NAD83(HARN)",DATUM["NAD83_High_Accuracy_Reference_Network",SPHEROID["GRS 1980",6378137,298.257222101,AUTHORITY["EPSG","7019"]],AUTHORITY["EPSG","6152"]],PRIMEM["Greenwich",0,AUTHORITY["EPSG","8901"]],UNIT["degree",0.0174532925199433,AUTHORITY["EPSG","9122"]],AUTHORITY["EPSG","4152"]],PROJECTION["Lambert_Conformal_Conic_2SP"],UNIT["foot",0.3048,AUTHORITY["EPSG","9002"]],AXIS["Easting",EAST],AXIS["Northing",NORTH],AUTHORITY["EPSG","2994"]]"#;

    #[test]
    fn wkt1_gives_the_code_and_the_projected_unit_not_the_geographic_one() {
        let units = CrsUnits::from_wkt(OREGON_FT);
        assert_eq!(units.epsg, Some(2994));
        assert_eq!(units.horizontal_name(), "international foot");
        assert_eq!(units.vertical_name(), "international foot");
    }

    #[test]
    fn a_wkt_without_a_code_gives_its_own_unit() {
        let text = r#"PROJCS["local",GEOGCS["g",UNIT["degree",0.0174532925199433]],UNIT["US survey foot",0.3048006096012192]]"#;
        let units = CrsUnits::from_wkt(text);
        assert_eq!((units.epsg, units.horizontal_name()), (None, "US survey foot"));
        let geographic =
            CrsUnits::from_wkt(r#"GEOGCS["WGS 84",UNIT["degree",0.0174532925199433],AUTHORITY["EPSG","4326"]]"#);
        assert_eq!((geographic.horizontal_name(), geographic.vertical_name()), ("degree", UNITS_OF_THE_FILE));
    }

    #[test]
    fn wkt2_compound_gives_both_parts() {
        let text = r#"COMPOUNDCRS["NAD83 / California zone 3 (ftUS) + NAVD88 height (ftUS)",
            PROJCRS["NAD83 / California zone 3 (ftUS)", BASEGEOGCRS["NAD83", DATUM["North American Datum 1983",
            ELLIPSOID["GRS 1980",6378137,298.257222101,LENGTHUNIT["metre",1]]]],
            CONVERSION["SPCS83 California zone 3 (US Survey feet)", METHOD["Lambert Conic Conformal (2SP)"]],
            CS[Cartesian,2], AXIS["easting (X)",east,LENGTHUNIT["US survey foot",0.304800609601219]],
            AXIS["northing (Y)",north,LENGTHUNIT["US survey foot",0.304800609601219]], ID["EPSG",2227]],
            VERTCRS["NAVD88 height (ftUS)", VDATUM["North American Vertical Datum 1988"], CS[vertical,1],
            AXIS["gravity-related height (H)",up,LENGTHUNIT["US survey foot",0.304800609601219]], ID["EPSG",6360]]]"#;
        let units = CrsUnits::from_wkt(text);
        assert_eq!(units.epsg, Some(2227));
        assert_eq!(units.horizontal_name(), "US survey foot");
        assert_eq!(units.vertical_name(), "US survey foot");
    }

    #[test]
    fn geotiff_keys_and_bare_codes_are_looked_up() {
        let utm = CrsUnits::from_geotiff_keys(&[(3072, 32611)]);
        assert_eq!((utm.epsg, utm.horizontal_name()), (Some(32611), "metre"));
        let feet = CrsUnits::from_geotiff_keys(&[(3072, 2227)]);
        assert_eq!(feet.horizontal_name(), "US survey foot");
        let keyed = CrsUnits::from_geotiff_keys(&[(3072, 32611), (3076, 9002), (4099, 9001)]);
        assert_eq!((keyed.horizontal_name(), keyed.vertical_name()), ("international foot", "metre"));
        assert_eq!(CrsUnits::default().horizontal_name(), UNITS_OF_THE_FILE);
    }

    #[test]
    fn broken_or_deep_wkt_gives_nothing_and_does_not_panic() {
        for text in ["", "PROJCS[", "PROJCS[\"a\",UNIT[\"foot\"", "[[[", &"A[".repeat(10_000), "GARBAGE"] {
            assert_eq!(CrsUnits::from_wkt(text).horizontal, None, "{text:.40}");
        }
    }
}
