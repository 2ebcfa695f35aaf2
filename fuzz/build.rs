//! The fuzz targets export the FMI functions from the program itself; the host of
//! `examples/fuzz_fmi/host.rs` finds them with `dlsym` on the program, so they go into its
//! dynamic symbol table.
fn main() {
    println!("cargo:rustc-link-arg-bins=-rdynamic");
}
