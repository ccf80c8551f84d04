//! Node transforms that collapse what they hold: a `scale` with a zero axis, or a `matrix`
//! whose linear part has no volume, flattens every mesh under the node to a plane, a line or
//! a point, which no renderer draws. glTF allows it (an animation may grow the node back), so
//! it is a warning, said by the bake and by the preview, never a silent disappearance.

use serde_json::Value;

use crate::document::Document;

/// Below this, a scale axis (or the cube root of |det| of a matrix's linear part) counts as
/// zero: far under any authored scale, far above f32 rounding of a real one.
pub const COLLAPSED: f64 = 1e-12;

/// Whether the node's own transform collapses space, and how it is written.
fn collapse(node: &Value) -> Option<String> {
    let floats = |key: &str| -> Option<Vec<f64>> {
        node.get(key)?
            .as_array()?
            .iter()
            .map(Value::as_f64)
            .collect::<Option<Vec<f64>>>()
    };
    if let Some(m) = floats("matrix").filter(|m| m.len() == 16) {
        let det = m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2])
            + m[8] * (m[1] * m[6] - m[5] * m[2]);
        return (det.abs().cbrt() <= COLLAPSED)
            .then(|| "its matrix has no volume (determinant 0)".to_owned());
    }
    let s = floats("scale").filter(|s| s.len() == 3)?;
    s.iter()
        .any(|v| v.abs() <= COLLAPSED)
        .then(|| format!("its scale {s:?} has a zero axis"))
}

/// Whether node `i` or any node under it holds a mesh (cycles and absurd depths cut off).
fn holds_mesh(nodes: &[Value], i: usize) -> bool {
    let mut stack = vec![i];
    let mut seen = vec![false; nodes.len()];
    while let Some(n) = stack.pop() {
        let Some(node) = nodes.get(n) else { continue };
        if std::mem::replace(&mut seen[n], true) {
            continue;
        }
        if node.get("mesh").is_some() {
            return true;
        }
        let children = node.get("children").and_then(Value::as_array);
        stack.extend(
            children
                .into_iter()
                .flatten()
                .filter_map(Value::as_u64)
                .map(|c| c as usize),
        );
    }
    false
}

/// One warning per node whose transform collapses a mesh under it, naming the node and why.
pub fn collapsed(doc: &Document) -> Vec<String> {
    let nodes = doc.array("nodes");
    nodes
        .iter()
        .enumerate()
        .filter_map(|(i, node)| {
            let why = collapse(node)?;
            holds_mesh(nodes, i).then(|| {
                format!(
                    "nodes[{i}]: {why}: the meshes under it are flattened to nothing and are \
                     not drawn (fur included)"
                )
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn a_zero_axis_or_a_flat_matrix_over_a_mesh_is_named() {
        let nodes = json!([
            { "scale": [1.0, 0.0, 1.0], "mesh": 0 },
            { "scale": [1.0, -2.0, 0.5], "mesh": 0 },
            { "matrix": [1,0,0,0, 0,1,0,0, 0,0,0,0, 0,0,0,1], "children": [3] },
            { "mesh": 0 },
            { "scale": [0.0, 0.0, 0.0] },
            { "scale": [1e-3, 1e-3, 1e-3], "mesh": 0 }
        ]);
        let nodes = nodes.as_array().unwrap();
        let found: Vec<usize> = (0..nodes.len())
            .filter(|&i| collapse(&nodes[i]).is_some() && holds_mesh(nodes, i))
            .collect();
        // A negative (mirroring) scale, a node without a mesh under it and a small but real
        // scale are not collapsed.
        assert_eq!(found, [0, 2]);
    }
}
