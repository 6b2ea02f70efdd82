//! The `raystep` command line.
