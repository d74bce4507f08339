//! Reading ROSS's export of a rotor (`rotor.save_mat(file, speed)`), behind the `mat` feature.

use std::path::Path;

use nalgebra::DMatrix;

use super::{DofLayout, RotorError, RotorMatrices};

impl RotorMatrices {
    /// Reads the MATLAB (v5) file that ROSS writes with `rotor.save_mat(file, speed=W)`: the
    /// keys `M`, `K`, `C`, `G` (square, of the same size, six DOFs a node,
    /// [`DofLayout::Ross6`]; `C` and `K` with the bearings at the speed `W`). Other keys
    /// (`nodes`) are ignored. Errors: the file cannot be read ([`RotorError::Io`]), is not a
    /// MAT file ([`RotorError::NotMatFile`]), misses a key or holds it in another type
    /// ([`RotorError::MissingMatrix`]), or holds matrices [`RotorMatrices::new`] refuses.
    ///
    /// ```no_run
    /// use jeffcott::rotor::RotorMatrices;
    /// let rotor = RotorMatrices::from_ross_mat("rotor_1200rpm.mat")?.lateral()?;
    /// # Ok::<(), jeffcott::rotor::RotorError>(())
    /// ```
    #[cfg_attr(docsrs, doc(cfg(feature = "mat")))]
    pub fn from_ross_mat(path: impl AsRef<Path>) -> Result<Self, RotorError> {
        let file = std::fs::File::open(path.as_ref()).map_err(|e| RotorError::Io(e.kind()))?;
        let mat = matfile::MatFile::parse(std::io::BufReader::new(file))
            .map_err(|_| RotorError::NotMatFile)?;
        let get = |key: &'static str| -> Result<DMatrix<f64>, RotorError> {
            let missing = || RotorError::MissingMatrix { key };
            let array = mat.find_by_name(key).ok_or_else(missing)?;
            let (rows, cols) = match array.size()[..] {
                [rows, cols] => (rows, cols),
                _ => return Err(missing()),
            };
            match array.data() {
                matfile::NumericData::Double { real, imag: None } if real.len() == rows * cols => {
                    Ok(DMatrix::from_column_slice(rows, cols, real))
                }
                _ => Err(missing()),
            }
        };
        Self::new(get("M")?, get("C")?, get("G")?, get("K")?, DofLayout::Ross6)
    }
}
