//! vdgview: the tool a level designer opens after a compile. It measures a `.vdg`
//! against its map's own BSP (`check`), and (issue 7) inspects, queries, renders and
//! flies through it. One module per subcommand.

pub mod check;
