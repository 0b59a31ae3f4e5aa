//! Rows of the columns, written in place: a batch of records fills the
//! rows it owns ([`ColumnsMut`], mutable slices of every column), so a LAZ
//! chunk decoded on one core writes its columns there while its records are
//! still in that core's cache ([`super::laz_chunks`]), and a batch of a LAS
//! file writes the rows appended for it.

use super::{Columns, classification_flags, extra_bytes::Field};

/// Mutable slices of the same rows of every column.
pub(crate) struct ColumnsMut<'a> {
    x: &'a mut [f64],
    y: &'a mut [f64],
    z: &'a mut [f64],
    rgb: Option<[&'a mut [u16]; 3]>,
    intensity: &'a mut [u16],
    classification: &'a mut [u8],
    flags: &'a mut [u8],
    return_number: &'a mut [u8],
    number_of_returns: &'a mut [u8],
    gps_time: Option<&'a mut [f64]>,
    point_source_id: &'a mut [u16],
    user_data: &'a mut [u8],
    scan_angle: &'a mut [f32],
    nir: Option<&'a mut [u16]>,
    extra: Vec<&'a mut [f64]>,
}

/// Splits a slice at `n`, the first part taken out of `slice`.
fn head<'a, T>(slice: &mut &'a mut [T], n: usize) -> &'a mut [T] {
    let (first, rest) = std::mem::take(slice).split_at_mut(n);
    *slice = rest;
    first
}

impl Columns {
    /// `n` more zero rows, of the columns a record of `format` with `extra` extra-bytes fields has.
    pub(crate) fn grow(&mut self, n: usize, format: &las::point::Format, extra: usize) {
        let to = self.len() + n;
        for column in [&mut self.x, &mut self.y, &mut self.z] {
            column.resize(to, 0.0);
        }
        if format.has_color {
            self.rgb.get_or_insert_with(Default::default).iter_mut().for_each(|c| c.resize(to, 0));
        }
        self.intensity.resize(to, 0);
        for column in [&mut self.classification, &mut self.flags, &mut self.return_number] {
            column.resize(to, 0);
        }
        self.number_of_returns.resize(to, 0);
        if format.has_gps_time {
            self.gps_time.get_or_insert_with(Vec::new).resize(to, 0.0);
        }
        self.point_source_id.resize(to, 0);
        self.user_data.resize(to, 0);
        self.scan_angle.resize(to, 0.0);
        if format.has_nir {
            self.nir.get_or_insert_with(Vec::new).resize(to, 0);
        }
        if self.extra.len() < extra {
            self.extra.resize_with(extra, Vec::new);
        }
        self.extra.iter_mut().for_each(|c| c.resize(to, 0.0));
    }

    /// `n` zero rows of the columns a record of `format` with `extra` extra-bytes fields has.
    pub(crate) fn zeroed(n: usize, format: &las::point::Format, extra: usize) -> Columns {
        Columns {
            x: vec![0.0; n],
            y: vec![0.0; n],
            z: vec![0.0; n],
            rgb: format.has_color.then(|| std::array::from_fn(|_| vec![0; n])),
            intensity: vec![0; n],
            classification: vec![0; n],
            flags: vec![0; n],
            return_number: vec![0; n],
            number_of_returns: vec![0; n],
            gps_time: format.has_gps_time.then(|| vec![0.0; n]),
            point_source_id: vec![0; n],
            user_data: vec![0; n],
            scan_angle: vec![0.0; n],
            nir: format.has_nir.then(|| vec![0; n]),
            extra: (0..extra).map(|_| vec![0.0; n]).collect(),
        }
    }

    /// Every row from `from` on, as slices.
    pub(crate) fn rows_from(&mut self, from: usize) -> ColumnsMut<'_> {
        ColumnsMut {
            x: &mut self.x[from..],
            y: &mut self.y[from..],
            z: &mut self.z[from..],
            rgb: self.rgb.as_mut().map(|[r, g, b]| [&mut r[from..], &mut g[from..], &mut b[from..]]),
            intensity: &mut self.intensity[from..],
            classification: &mut self.classification[from..],
            flags: &mut self.flags[from..],
            return_number: &mut self.return_number[from..],
            number_of_returns: &mut self.number_of_returns[from..],
            gps_time: self.gps_time.as_mut().map(|t| &mut t[from..]),
            point_source_id: &mut self.point_source_id[from..],
            user_data: &mut self.user_data[from..],
            scan_angle: &mut self.scan_angle[from..],
            nir: self.nir.as_mut().map(|c| &mut c[from..]),
            extra: self.extra.iter_mut().map(|c| &mut c[from..]).collect(),
        }
    }
}

impl<'a> ColumnsMut<'a> {
    /// The first `n` rows, taken out of these.
    pub(crate) fn take_head(&mut self, n: usize) -> ColumnsMut<'a> {
        ColumnsMut {
            x: head(&mut self.x, n),
            y: head(&mut self.y, n),
            z: head(&mut self.z, n),
            rgb: self.rgb.as_mut().map(|[r, g, b]| [head(r, n), head(g, n), head(b, n)]),
            intensity: head(&mut self.intensity, n),
            classification: head(&mut self.classification, n),
            flags: head(&mut self.flags, n),
            return_number: head(&mut self.return_number, n),
            number_of_returns: head(&mut self.number_of_returns, n),
            gps_time: self.gps_time.as_mut().map(|t| head(t, n)),
            point_source_id: head(&mut self.point_source_id, n),
            user_data: head(&mut self.user_data, n),
            scan_angle: head(&mut self.scan_angle, n),
            nir: self.nir.as_mut().map(|c| head(c, n)),
            extra: self.extra.iter_mut().map(|c| head(c, n)).collect(),
        }
    }

    /// Writes `batch`'s records into these rows (as many as it holds), one
    /// column at a time, each column a job handed to `run`: run at once
    /// (a chunk on its core) or spawned (a batch on every core).
    pub(crate) fn fill<'s>(
        self,
        batch: &'s las::PointData,
        fields: &'s [Field],
        run: &mut dyn FnMut(Box<dyn FnOnce() + Send + 's>),
    ) where
        'a: 's,
    {
        fn put<T>(out: &mut [T], values: impl Iterator<Item = T>) {
            out.iter_mut().zip(values).for_each(|(o, v)| *o = v);
        }
        let extended = batch.format().is_extended;
        let record_len = batch.record_len();
        let records = move || batch.raw_bytes().chunks_exact(record_len);
        let ColumnsMut {
            x,
            y,
            z,
            rgb,
            intensity,
            classification,
            flags,
            return_number,
            number_of_returns,
            gps_time,
            point_source_id,
            user_data,
            scan_angle,
            nir,
            extra,
        } = self;
        run(Box::new(move || put(x, batch.x())));
        run(Box::new(move || put(y, batch.y())));
        run(Box::new(move || put(z, batch.z())));
        if let (Some([r, g, b]), Some(colours)) = (rgb, batch.rgb()) {
            run(Box::new(move || {
                for (k, (cr, cg, cb)) in colours.enumerate().take(r.len()) {
                    (r[k], g[k], b[k]) = (cr, cg, cb);
                }
            }));
        }
        run(Box::new(move || put(intensity, batch.intensity())));
        run(Box::new(move || put(classification, batch.classification())));
        run(Box::new(move || put(flags, records().map(|r| classification_flags(r, extended)))));
        run(Box::new(move || {
            put(return_number, batch.return_number());
            put(number_of_returns, batch.number_of_returns());
        }));
        if let (Some(out), Some(t)) = (gps_time, batch.gps_time()) {
            run(Box::new(move || put(out, t)));
        }
        run(Box::new(move || {
            put(point_source_id, batch.point_source_id());
            put(user_data, batch.user_data());
        }));
        run(Box::new(move || put(scan_angle, batch.scan_angle_degrees())));
        if let (Some(out), Some(n)) = (nir, batch.nir()) {
            run(Box::new(move || put(out, n)));
        }
        for (column, field) in extra.into_iter().zip(fields) {
            run(Box::new(move || put(column, records().map(|r| field.value(r)))));
        }
    }
}
