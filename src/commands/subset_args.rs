//! What `convert` writes of its input: the points in a clip region, of
//! some classes, passing attribute filters and of some returns. The same
//! flags, with the same parsers and meanings, as the viewing commands'
//! (scene_args.rs), applied to a file's records (or a loaded cloud's
//! splats) before they are written: every test in f64 file coordinates.

use std::path::Path;

use anyhow::Result;
use glam::DVec3;
use pointblend::cloud::PointCloud;
use pointblend::cloud::attributes::Attributes;
use pointblend::cloud::records::Records;
use pointblend::frame::clip::{self, ClipBox, ClipRegion, Hidden};
use pointblend::style::{Filter, Returns, filter};

#[derive(clap::Args, Debug, Clone, Default)]
pub struct SubsetArgs {
    /// Write only the points in the box MINX,MINY,MINZ,MAXX,MAXY,MAXZ (file coordinates; edges kept).
    #[arg(long = "clip-box", value_parser = |t: &str| ClipBox::parse(t).map_err(|e| e.to_string()), allow_hyphen_values = true)]
    pub clip_box: Option<ClipBox>,
    /// Which side of --clip-box is left out: outside (write the box's contents) or inside (cut the box away).
    #[arg(long = "clip-hide", value_parser = super::scene_args::parse_hidden, requires = "clip_box")]
    pub clip_hide: Option<Hidden>,
    /// Write only the points on the side of a plane NX,NY,NZ,D where n·x + d >= 0 (repeatable, at most 6).
    #[arg(long = "clip-plane", value_parser = |t: &str| clip::parse_plane(t).map_err(|e| e.to_string()), allow_hyphen_values = true)]
    pub clip_planes: Vec<[f64; 4]>,
    /// Write only these ASPRS classes, e.g. 2,6.
    #[arg(long, value_delimiter = ',', value_parser = super::scene_args::parse_class)]
    pub classes: Vec<u8>,
    /// Write only the points whose attribute NAME lies in MIN..MAX or is one of V1,V2,...:
    /// NAME=MIN..MAX or NAME=V1,V2 (repeatable; all must hold).
    #[arg(long = "filter", value_parser = |t: &str| t.parse::<Filter>(), allow_hyphen_values = true)]
    pub filters: Vec<Filter>,
    /// Write only these returns: first, last, only (single returns) or a return number N.
    #[arg(long, value_parser = |t: &str| t.parse::<Returns>())]
    pub returns: Option<Returns>,
}

impl SubsetArgs {
    /// Whether any flag asks for a subset.
    pub fn is_given(&self) -> bool {
        self.clip_box.is_some()
            || !self.clip_planes.is_empty()
            || !self.classes.is_empty()
            || !self.filters.is_empty()
            || self.returns.is_some()
    }

    /// The points of `cloud` the flags keep, with their attributes; the
    /// count left out.
    pub fn apply(&self, cloud: PointCloud, input: &Path) -> Result<(PointCloud, usize)> {
        if !self.is_given() {
            return Ok((cloud, 0));
        }
        let keep = self.kept(cloud.len(), &cloud.attributes, |i| cloud.file_position(i))?;
        refuse_none_kept(input, keep.len(), cloud.len())?;
        let kept = PointCloud { attributes: cloud.attributes.gather(&keep), ..cloud.select(&keep) };
        Ok((kept, cloud.len() - keep.len()))
    }

    /// The horizontal box (x and y, file coordinates) that holds every
    /// point the flags keep: `--clip-box`'s when it keeps its inside, else
    /// everywhere. A streamed input reads only the nodes meeting it.
    pub fn region(&self) -> (glam::DVec2, glam::DVec2) {
        match self.clip_box {
            Some(b) if self.clip_hide.unwrap_or_default() == Hidden::Outside => {
                (glam::DVec2::new(b.min[0], b.min[1]), glam::DVec2::new(b.max[0], b.max[1]))
            }
            _ => (glam::DVec2::NEG_INFINITY, glam::DVec2::INFINITY),
        }
    }

    /// The records the flags keep, ascending.
    pub fn kept_records(&self, records: &Records, input: &Path) -> Result<Vec<u32>> {
        let keep = self.kept(records.len(), &records.attributes, |i| records.positions[i])?;
        refuse_none_kept(input, keep.len(), records.len())?;
        Ok(keep)
    }

    /// Which of `n` points, with `attributes` and at file positions
    /// `position(i)` (f64), the flags keep.
    fn kept(&self, n: usize, attributes: &Attributes, position: impl Fn(usize) -> DVec3) -> Result<Vec<u32>> {
        let classes = (!self.classes.is_empty()).then_some(self.classes.as_slice());
        let keep = filter::kept_of(attributes, n, classes, &self.filters, self.returns).map_err(anyhow::Error::msg)?;
        let region = ClipRegion {
            clip_box: self.clip_box.map(|b| ClipBox { hide: self.clip_hide.unwrap_or_default(), ..b }),
            planes: self.clip_planes.clone(),
        };
        region.check()?;
        if region.is_empty() {
            return Ok(keep);
        }
        Ok(keep.into_iter().filter(|&i| region.keeps_file_point(position(i as usize))).collect())
    }
}

/// Refuses a subset that keeps none of `total` points (a box or filter that
/// misses the file), before anything is written: an empty output is a mistake.
fn refuse_none_kept(input: &Path, kept: usize, total: usize) -> Result<()> {
    if kept == 0 && total > 0 {
        anyhow::bail!(
            "{}: the subset keeps none of its {total} points, so nothing is written (`pointblend info` gives its bounds and attributes)",
            input.display()
        );
    }
    Ok(())
}
