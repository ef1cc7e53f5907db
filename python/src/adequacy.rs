//! `adequacy`: the library's mesh-adequacy diagnostic (`scene::adequacy`, over
//! `population::adequacy`) of a scene's whole run from its results, for a run in memory or one
//! loaded back; a run into a folder has it in `adequacy.json` already.

use crate::errors::scene_error;
use crate::results::Results;
use crate::scene::PyScene;
use pyo3::prelude::*;

/// The diagnostic of `scene`'s whole run `results` as the text of the command's
/// `adequacy.json` (the same re-track of the first `output.adequacy_sample` particles), or
/// `None` on an analytic flow.
#[pyfunction]
pub(crate) fn adequacy(
    py: Python<'_>,
    scene: &Bound<'_, PyScene>,
    results: &Bound<'_, Results>,
) -> PyResult<Option<String>> {
    let scene = &scene.get().inner;
    let records = &results.get().output.records;
    py.detach(|| {
        pseudorigid::scene::adequacy::adequacy(scene, records, false)?
            .map(|a| a.json())
            .transpose()
    })
    .map_err(|e| scene_error(py, &e))
}
