//! Scene lights: point and directional, with colour, intensity and an
//! optional inverse-square falloff (Gunjee et al. §4.1 light point lights;
//! directional lights are the limit of a point light far away).
//!
//! A frame without lights is lit by the headlight of [`super::Shading`], as
//! before lights existed. A frame with lights is lit by them alone (the
//! ambient term stays), each light's share scaled by the transmittance its
//! light keeps on the way to the surface: the translucent shadow of
//! `crate::shadow`. [`Lights`] is a fixed-size set so that render settings
//! stay plain `Copy` data; positions and directions are in the scene's
//! world frame (the flattened scene's coordinates, model units).

use glam::Vec3;

/// Most lights a frame takes (the GPU keeps one byte of shadow per light
/// and splat, in two 4-byte attributes).
pub const MAX_LIGHTS: usize = 8;

/// Where light comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LightKind {
    /// A point light at this world position.
    Point(Vec3),
    /// Parallel light travelling along this unit world direction.
    Directional(Vec3),
}

/// One light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    pub kind: LightKind,
    /// Linear colour, 0..1 per channel.
    pub colour: Vec3,
    pub intensity: f32,
    /// Intensity / d² (d in model units) instead of no falloff; point lights only.
    pub inverse_square: bool,
}

/// A light that cannot be used, said in one line.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LightError {
    #[error("at most {MAX_LIGHTS} lights are supported, {0} were given")]
    TooMany(usize),
    #[error("a light's {0} must be finite numbers")]
    NotFinite(&'static str),
    #[error("a directional light's direction must not be zero")]
    ZeroDirection,
    #[error("a light's intensity must be finite and >= 0, not {0}")]
    Intensity(f32),
    #[error("a light's colour must be three values in 0..255")]
    Colour,
    #[error("'{0}' is not a light position X,Y,Z (three finite numbers)")]
    Position(String),
    #[error("a light at {0} is beyond {MAX_LIGHT_COORDINATE:e} in some coordinate: its distance squared leaves f32")]
    TooFar(Vec3),
}

/// The largest coordinate a point light may have: beyond it the squared
/// distances of its falloff and shadows overflow f32.
pub const MAX_LIGHT_COORDINATE: f32 = 1e15;

impl Light {
    /// A white point light of intensity 1 with no falloff.
    pub fn point(position: Vec3) -> Self {
        Self { kind: LightKind::Point(position), colour: Vec3::ONE, intensity: 1.0, inverse_square: false }
    }

    /// A white directional light of intensity 1 travelling along `direction`.
    pub fn directional(direction: Vec3) -> Self {
        Self {
            kind: LightKind::Directional(direction.normalize_or_zero()),
            colour: Vec3::ONE,
            intensity: 1.0,
            inverse_square: false,
        }
    }

    /// Checks that the light can be used.
    pub fn validate(&self) -> Result<(), LightError> {
        match self.kind {
            LightKind::Point(p) if !p.is_finite() => return Err(LightError::NotFinite("position")),
            LightKind::Point(p) if p.abs().max_element() > MAX_LIGHT_COORDINATE => return Err(LightError::TooFar(p)),
            LightKind::Directional(d) if !d.is_finite() => return Err(LightError::NotFinite("direction")),
            LightKind::Directional(d) if d.length_squared() < 1e-12 => return Err(LightError::ZeroDirection),
            _ => {}
        }
        if !(self.intensity.is_finite() && self.intensity >= 0.0) {
            return Err(LightError::Intensity(self.intensity));
        }
        if !(self.colour.is_finite() && self.colour.cmpge(Vec3::ZERO).all() && self.colour.cmple(Vec3::ONE).all()) {
            return Err(LightError::Colour);
        }
        Ok(())
    }

    /// At world point `p`: the unit direction towards the light and the
    /// light arriving there unshadowed (colour × intensity × falloff).
    pub fn incident(&self, p: Vec3) -> (Vec3, Vec3) {
        let radiance = self.colour * self.intensity;
        match self.kind {
            LightKind::Point(position) => {
                let to_light = position - p;
                let d2 = to_light.length_squared();
                let dir = if d2 > 0.0 { to_light / d2.sqrt() } else { Vec3::ZERO };
                let falloff = if self.inverse_square { 1.0 / d2.max(1e-12) } else { 1.0 };
                (dir, radiance * falloff)
            }
            LightKind::Directional(d) => (-d, radiance),
        }
    }

    /// `--light X,Y,Z`: a white point light at that position.
    pub fn parse_point(text: &str) -> Result<Self, LightError> {
        let values: Vec<f32> = text
            .split(',')
            .map(|v| v.trim().parse::<f32>())
            .collect::<Result<_, _>>()
            .map_err(|_| LightError::Position(text.into()))?;
        match values[..] {
            [x, y, z] if x.is_finite() && y.is_finite() && z.is_finite() => Ok(Self::point(Vec3::new(x, y, z))),
            _ => Err(LightError::Position(text.into())),
        }
    }
}

/// Up to [`MAX_LIGHTS`] lights, as plain `Copy` data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lights {
    lights: [Light; MAX_LIGHTS],
    len: usize,
}

impl Default for Lights {
    fn default() -> Self {
        Self { lights: [Light::point(Vec3::ZERO); MAX_LIGHTS], len: 0 }
    }
}

impl Lights {
    /// The lights, validated; more than [`MAX_LIGHTS`] is an error.
    pub fn new(lights: &[Light]) -> Result<Self, LightError> {
        if lights.len() > MAX_LIGHTS {
            return Err(LightError::TooMany(lights.len()));
        }
        let mut out = Self::default();
        for light in lights {
            light.validate()?;
            out.lights[out.len] = *light;
            out.len += 1;
        }
        Ok(out)
    }

    pub fn as_slice(&self) -> &[Light] {
        &self.lights[..self.len]
    }

    pub fn as_mut_slice(&mut self) -> &mut [Light] {
        &mut self.lights[..self.len]
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Adds a light; refused past [`MAX_LIGHTS`] or when it is not usable.
    pub fn push(&mut self, light: Light) -> Result<(), LightError> {
        light.validate()?;
        if self.len == MAX_LIGHTS {
            return Err(LightError::TooMany(MAX_LIGHTS + 1));
        }
        self.lights[self.len] = light;
        self.len += 1;
        Ok(())
    }

    /// Removes the light at `index`, if there is one.
    pub fn remove(&mut self, index: usize) {
        if index < self.len {
            self.lights.copy_within(index + 1..self.len, index);
            self.len -= 1;
        }
    }
}

/// How a frame with lights finds the light that reaches each splat.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ShadowMethod {
    /// Gunjee's translucent shadow map, one table per light (`shadow::table`).
    #[default]
    Tsm,
    /// A shadow ray from each splat to each light through the splats (`shadow::rays`): TSM's ruler.
    Exact,
    /// No shadows: every light reaches every splat.
    Off,
}

impl ShadowMethod {
    pub const ALL: [ShadowMethod; 3] = [ShadowMethod::Tsm, ShadowMethod::Exact, ShadowMethod::Off];

    pub fn name(self) -> &'static str {
        match self {
            ShadowMethod::Tsm => "tsm",
            ShadowMethod::Exact => "exact",
            ShadowMethod::Off => "off",
        }
    }
}

crate::by_name!(ShadowMethod, "shadow method");

/// The shadow settings of a frame with lights.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ShadowSettings {
    pub method: ShadowMethod,
    /// TSM cells per light: k_pol × k_az (Gunjee Eq. 2-3).
    pub cells: [u32; 2],
}

/// Default TSM table: cells about as fine as the splats of a 362K-point
/// scan seen from a light two model radii away (docs/BENCHMARKS.md, "TSM").
pub const DEFAULT_TSM_CELLS: [u32; 2] = [512, 512];

/// Most cells a TSM table may have on a side.
pub const MAX_TSM_CELLS: u32 = 8192;

impl Default for ShadowSettings {
    fn default() -> Self {
        Self { method: ShadowMethod::Tsm, cells: DEFAULT_TSM_CELLS }
    }
}

/// A TSM table size, POLxAZ (or one number for both): `--shadows tsm-POLxAZ`.
pub fn parse_cells(text: &str) -> Result<[u32; 2], String> {
    let one = |v: &str| {
        v.trim()
            .parse::<u32>()
            .ok()
            .filter(|n| (1..=MAX_TSM_CELLS).contains(n))
            .ok_or_else(|| format!("'{text}' is not a TSM table size: POLxAZ or N, each 1..={MAX_TSM_CELLS}"))
    };
    match text.split_once(['x', 'X']) {
        Some((p, a)) => Ok([one(p)?, one(a)?]),
        None => one(text).map(|n| [n, n]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parsing_and_limits_give_one_line_errors() {
        assert_eq!(Light::parse_point("1, 2,3").unwrap().kind, LightKind::Point(Vec3::new(1.0, 2.0, 3.0)));
        for bad in ["1,2", "1,2,NaN", "1,2,x", "1,2,3,4", "inf,0,0"] {
            let e = Light::parse_point(bad).unwrap_err().to_string();
            assert!(e.contains(bad) && !e.contains('\n'), "{e}");
        }
        let nine = vec![Light::point(Vec3::ZERO); MAX_LIGHTS + 1];
        assert_eq!(Lights::new(&nine), Err(LightError::TooMany(9)));
        let mut lights = Lights::new(&nine[..MAX_LIGHTS]).unwrap();
        assert_eq!(lights.push(Light::point(Vec3::ONE)), Err(LightError::TooMany(9)));
        lights.remove(0);
        assert_eq!(lights.len(), MAX_LIGHTS - 1);
        assert_eq!(Light::directional(Vec3::ZERO).validate(), Err(LightError::ZeroDirection));
        assert_eq!(parse_cells("64x128"), Ok([64, 128]));
        assert_eq!(parse_cells("1"), Ok([1, 1]));
        for bad in ["0", "9000", "2x", "axb"] {
            assert!(parse_cells(bad).unwrap_err().contains(bad));
        }
    }

    #[test]
    fn inverse_square_falls_off_and_directional_does_not() {
        let mut light = Light::point(Vec3::new(0.0, 2.0, 0.0));
        let (dir, plain) = light.incident(Vec3::ZERO);
        assert_eq!((dir, plain), (Vec3::Y, Vec3::ONE));
        light.inverse_square = true;
        assert!((light.incident(Vec3::ZERO).1 - Vec3::splat(0.25)).length() < 1e-6);
        let sun = Light::directional(Vec3::new(0.0, -3.0, 0.0));
        assert_eq!(sun.incident(Vec3::splat(100.0)), (Vec3::Y, Vec3::ONE));
    }
}
