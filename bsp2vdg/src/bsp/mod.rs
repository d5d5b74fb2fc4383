//! BSP file reading.
