//! A streamed file's points inside a horizontal box, at full resolution:
//! what `profile` and `measure --polygon` read of a COPC file or URL. The
//! hierarchy is walked from the root through every node whose cube meets
//! the box (reading the pages the walk reaches), and every such node that
//! holds points is read through the loader pool ([`super::load`]: nearby
//! chunks merged, `--disk-cache` used) and decoded in parallel, at every level: COPC
//! spreads a region's points over all the levels above it. The records
//! come back as they are in the file too, so an export copies them.

use glam::{DVec2, DVec3};

use super::{CopcError, CopcStream, decode};
use crate::cloud::las_file::{self, Columns};
use crate::cloud::records::{RecordSource, Records};

impl CopcStream {
    /// The nodes whose cube meets the box `lo..hi` (x and y, file
    /// coordinates) and holds points, in file order.
    fn nodes_meeting(&mut self, (lo, hi): (DVec2, DVec2)) -> Result<Vec<u32>, CopcError> {
        let root = las::copc::VoxelKey { l: 0, x: 0, y: 0, z: 0 };
        let Some(root) = self.tree.node(&root) else { return Ok(Vec::new()) };
        let (mut stack, mut chosen) = (vec![root], Vec::new());
        while let Some(n) = stack.pop() {
            self.read_page(n);
            if let Some(reason) = self.failed.get(&n) {
                return Err(CopcError::new(self.name(), format!("a node of the region cannot be read: {reason}")));
            }
            let node = &self.tree.nodes[n as usize];
            let (min, side) = self.tree.cube(&node.key);
            let meets = min.x <= hi.x && min.x + side >= lo.x && min.y <= hi.y && min.y + side >= lo.y;
            if !meets {
                continue;
            }
            if node.points > 0 {
                chosen.push(n);
            }
            stack.extend(node.children.iter().copied());
        }
        chosen.sort_by_key(|&n| self.tree.nodes[n as usize].offset);
        Ok(chosen)
    }

    /// Every point of the nodes meeting the box `lo..hi` (x and y, file
    /// coordinates) as records: a superset of the points in the box, which
    /// the caller selects from.
    pub fn region_records(&mut self, (lo, hi): (DVec2, DVec2)) -> Result<Records, CopcError> {
        let nodes = self.nodes_meeting((lo, hi))?;
        self.records_of(&nodes)
    }

    /// The root node's points as records: a sample of the whole file.
    pub fn root_records(&mut self) -> Result<Records, CopcError> {
        let root = las::copc::VoxelKey { l: 0, x: 0, y: 0, z: 0 };
        let nodes: Vec<u32> = self.tree.node(&root).into_iter().collect();
        self.records_of(&nodes)
    }

    /// Every point of `nodes` (in file order) as records.
    fn records_of(&mut self, nodes: &[u32]) -> Result<Records, CopcError> {
        let total: u64 = nodes.iter().map(|&n| u64::from(self.tree.nodes[n as usize].points)).sum();
        let bar = crate::progress::bar(total, "reading the region's nodes", self.options.progress);
        let (source, header, tree, disk) = (self.source.as_ref(), &self.header, &self.tree, self.disk.as_ref());
        // Through the loader pool: nearby chunks merged, four requests in flight, `--disk-cache` used.
        let fetch = super::load::Fetch { source, header, tree, disk, memory: None };
        let decode = |n: u32, bytes: &[u8]| {
            let node = &tree.nodes[n as usize];
            decode::decode_with_records(header, bytes, node.points, tree.cube(&node.key)).map_err(|reason| {
                let k = node.key;
                format!("node {}-{}-{}-{}: {reason}", k.l, k.x, k.y, k.z)
            })
        };
        let mut decoded = fetch.decoded(nodes, &decode, &|points| bar.inc(points));
        // In file order, as the nodes were given.
        let order: std::collections::HashMap<u32, usize> = nodes.iter().enumerate().map(|(k, &n)| (n, k)).collect();
        decoded.sort_by_key(|(n, _)| order[n]);
        bar.finish();
        let (mut columns, mut records) = (Columns::default(), Vec::new());
        for (_, result) in decoded {
            let (c, r) = result.map_err(|reason| CopcError::new(self.name(), reason))?;
            columns.extend(&c);
            records.extend(r);
        }
        let mut warnings = Vec::new();
        let (data, attributes) = columns.finish(&self.header.fields, String::new(), &mut warnings);
        let column = |name: &str| &data.vertex_columns[name];
        let (x, y, z) = (column("x"), column("y"), column("z"));
        Ok(Records {
            positions: (0..data.vertex_count).map(|i| DVec3::new(x[i], y[i], z[i])).collect(),
            attributes,
            units: las_file::crs_units(&self.header.las),
            crs: las_file::crs(&self.header.las),
            source: RecordSource::Raw { header: Box::new(self.header.las.clone()), records },
        })
    }
}
