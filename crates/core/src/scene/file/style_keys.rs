//! An object's colour, opacity and filters by attribute in a scene file: the
//! keys `color_by`, `colormap`, `range`, `classes`, `class_opacity`,
//! `opacity_by`, `filter` and `returns`, read into a [`Style`] (see [`crate::style`]).

use super::{ObjectEntry, Reader, SceneError};
use crate::style::{Style, parse};

impl Reader<'_> {
    /// The object's colour and opacity by attribute (`color_by`, `colormap`, `range`, `classes`, `class_opacity`, `opacity_by`).
    pub(super) fn style(&self, entry: &ObjectEntry) -> Result<Style, SceneError> {
        let mut style = Style::default();
        if let Some(by) = &entry.color_by {
            style.color_by = Some(by.get_ref().parse().map_err(|e| self.at(Some(by.span()), e))?);
        }
        if let Some(map) = &entry.colormap {
            style.colormap = map.get_ref().parse().map_err(|e| self.at(Some(map.span()), e))?;
        }
        if let Some(range) = &entry.range {
            let [lo, hi] = *range.get_ref();
            style.range = Some(parse::range(&format!("{lo},{hi}")).map_err(|e| self.at(Some(range.span()), e))?);
        }
        style.classes = entry.classes.as_ref().map(|c| c.get_ref().clone());
        if let Some(table) = &entry.class_opacity {
            let pairs: Vec<String> = table.get_ref().iter().map(|(c, a)| format!("{c}:{a}")).collect();
            style.class_opacity = parse::class_opacity(&pairs.join(",")).map_err(|e| self.at(Some(table.span()), e))?;
        }
        style.opacity_by = entry.opacity_by.as_ref().map(|o| o.get_ref().clone());
        if let Some(filters) = &entry.filter {
            let parsed: Result<Vec<_>, String> = filters.get_ref().iter().map(|f| f.parse()).collect();
            style.filters = parsed.map_err(|e| self.at(Some(filters.span()), e))?;
        }
        if let Some(returns) = &entry.returns {
            style.returns = Some(returns.get_ref().parse().map_err(|e| self.at(Some(returns.span()), e))?);
        }
        Ok(style)
    }
}
