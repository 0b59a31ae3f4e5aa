//! A COPC file's header: the LAS 1.4 header and VLRs, the COPC info VLR
//! (octree centre, half-size, root spacing, root hierarchy page) and the
//! LAZ VLR, read from the file's first bytes only (COPC 1.0, sections 3-4).
//!
//! The `las` crate's `Header::new` also seeks to the EVLRs at the end of the
//! file; a streamed file reads none of them (the hierarchy is reached from
//! the info VLR), so the raw header and VLRs are read here and handed to the
//! crate's `Builder`.

use las::copc::CopcInfoVlr;
use laz::LazVlr;

use super::CopcError;
use super::source::ByteSource;
use crate::cloud::las_file::extra_bytes;

/// What a streamed file's header says.
pub struct CopcHeader {
    pub las: las::Header,
    pub info: CopcInfoVlr,
    /// Offset and size of the root hierarchy page.
    pub root_page: (u64, u64),
    /// How its chunks are compressed (`None` for a file held whole in memory, which has none).
    pub laz: Option<LazVlr>,
    /// The extra-bytes fields each record carries.
    pub fields: Vec<extra_bytes::Field>,
    pub warnings: Vec<String>,
    /// The file's length in bytes.
    pub file_len: u64,
}

/// Largest header plus VLRs read (the offset to the points is a u32, but a
/// real COPC file's VLRs are a few KiB).
const MAX_HEADER_BYTES: u64 = 16 << 20;

pub fn read(source: &dyn ByteSource) -> Result<CopcHeader, CopcError> {
    let name = source.name();
    let bad = |reason: String| CopcError::new(name, format!("not a COPC file: {reason}"));
    let file_len = source.len();
    let head = source.read(0, 375.min(file_len))?;
    let raw = las::raw::Header::read_from(&head[..]).map_err(|e| bad(e.to_string()))?;
    let least = raw.version.header_size();
    if raw.header_size < least {
        return Err(bad(format!(
            "its header says it is {} bytes long, but a LAS {} header takes {least}",
            raw.header_size, raw.version
        )));
    }
    let points_at = u64::from(raw.offset_to_point_data);
    if points_at > file_len.min(MAX_HEADER_BYTES) || points_at < 375 {
        return Err(bad(format!("the points start at byte {points_at}, in a file of {file_len} bytes")));
    }
    if u64::from(raw.header_size) > points_at {
        return Err(bad(format!("its header is {} bytes long, past the points at byte {points_at}", raw.header_size)));
    }
    let bytes = source.read(0, points_at)?;
    let mut cursor = &bytes[usize::from(raw.header_size)..];
    let vlr_count = raw.number_of_variable_length_records;
    let mut raw = raw;
    // The EVLRs lie at the end; nothing streamed needs them.
    raw.evlr = None;
    let mut builder = las::Builder::new(raw).map_err(|e| bad(e.to_string()))?;
    for _ in 0..vlr_count {
        let vlr = las::raw::Vlr::read_from(&mut cursor, false).map_err(|e| bad(format!("its VLRs: {e}")))?;
        builder.vlrs.push(las::Vlr::new(vlr));
    }
    let info_vlr = builder
        .vlrs
        .iter()
        .find(|v| v.user_id == las::copc::USER_ID && v.record_id == CopcInfoVlr::RECORD_ID)
        .ok_or_else(|| bad("it has no COPC info VLR".into()))?;
    let info = CopcInfoVlr::try_from(info_vlr).map_err(|e| bad(format!("its COPC info VLR: {e}")))?;
    // The root page's offset and size are private in the crate's struct: bytes 40..56 of the record.
    let word = |at: usize| u64::from_le_bytes(info_vlr.data[at..at + 8].try_into().expect("eight bytes"));
    let root_page = (word(40), word(48));
    let laz_vlr = builder
        .vlrs
        .iter()
        .find(|v| v.user_id == "laszip encoded" && v.record_id == 22204)
        .ok_or_else(|| bad("it has no LAZ VLR (COPC points are LAZ-compressed)".into()))?;
    let laz = LazVlr::read_from(&laz_vlr.data[..]).map_err(|e| bad(format!("its LAZ VLR: {e}")))?;
    let las = builder.into_header().map_err(|e| bad(e.to_string()))?;
    let format = las.point_format();
    if !format.is_extended {
        return Err(bad(format!("point format {} (COPC uses 6, 7 or 8)", format.to_u8().unwrap_or(255))));
    }
    let items: u64 = laz.items().iter().map(|i| u64::from(i.size())).sum();
    if items != u64::from(format.len()) {
        return Err(bad(format!("the LAZ items take {items} bytes, the records {}", format.len())));
    }
    let geometry_ok =
        [info.center_x, info.center_y, info.center_z, info.halfsize, info.spacing].iter().all(|v| v.is_finite())
            && info.halfsize > 0.0
            && info.spacing > 0.0;
    if !geometry_ok {
        return Err(bad(format!(
            "the info VLR's octree is centre ({}, {}, {}), half-size {}, spacing {}",
            info.center_x, info.center_y, info.center_z, info.halfsize, info.spacing
        )));
    }
    let descriptors = extra_bytes::descriptors(&las, format.extra_bytes).map_err(bad)?;
    Ok(CopcHeader {
        las,
        info,
        root_page,
        laz: Some(laz),
        fields: descriptors.fields,
        warnings: descriptors.warnings,
        file_len,
    })
}
