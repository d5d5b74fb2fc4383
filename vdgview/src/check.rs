//! `vdgview check MAP.bsp FILE.vdg`: quality of a graph against the map (SPEC §8).
