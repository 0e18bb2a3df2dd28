//! Output files of the CLI written all or nothing: each is checked before the work
//! (its folder exists and takes a new file), written to a temporary file beside it and
//! renamed onto it only when the command succeeds, so a failed command leaves no
//! partial or stale output behind.

use std::fs::File;
use std::path::{Path, PathBuf};

/// An output file on its way: the temporary file beside `target` is created at once
/// (so an unwritable target fails before the work), removed if the command fails
/// (dropped without [`Staged::commit`]).
#[must_use = "an uncommitted output is removed"]
pub struct Staged {
    target: PathBuf,
    temp: PathBuf,
}

impl Staged {
    /// Stages `target` (written through it when it is a symbolic link,
    /// [`sim::through_links`]): an error if it cannot take an output ([`sim::output_problem`])
    /// or its folder cannot take a file.
    pub fn new(target: &Path) -> Result<Staged, String> {
        let shown = target.display();
        if let Some(problem) = sim::output_problem(target) {
            return Err(problem);
        }
        let target = &sim::through_links(target);
        let temp = sim::temp_beside(target).ok_or_else(|| format!("{shown}: not a file name"))?;
        File::create(&temp).map_err(|e| format!("{shown}: cannot write: {e}"))?;
        Ok(Staged {
            target: target.to_path_buf(),
            temp,
        })
    }

    /// Stages a PNG image: as [`Staged::new`], and the name must end in `.png` (the
    /// only format written).
    pub fn png(target: &Path) -> Result<Staged, String> {
        let is_png = target
            .extension()
            .is_some_and(|x| x.eq_ignore_ascii_case("png"));
        if !is_png {
            return Err(format!(
                "{}: the image is written as PNG: give a name ending in .png",
                target.display()
            ));
        }
        Staged::new(target)
    }

    /// Where to write the contents.
    pub fn temp_path(&self) -> &Path {
        &self.temp
    }

    /// Renames the written temporary file onto the target.
    pub fn commit(self) -> Result<(), String> {
        std::fs::rename(&self.temp, &self.target)
            .map_err(|e| format!("{}: {e}", self.target.display()))
        // the drop then finds no temporary file
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.temp);
    }
}
