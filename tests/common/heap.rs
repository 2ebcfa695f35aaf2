//! The bytes in use on glibc's heap, for the tests and benchmarks that count what an FMU keeps
//! (every allocator in the process is glibc's malloc: the host's and each FMU binary's own copy
//! of Rust's std).

/// glibc's `struct mallinfo2` (glibc ≥ 2.33).
#[repr(C)]
#[derive(Default)]
struct MallInfo2 {
    arena: usize,
    ordblks: usize,
    smblks: usize,
    hblks: usize,
    hblkhd: usize,
    usmblks: usize,
    fsmblks: usize,
    uordblks: usize,
    fordblks: usize,
    keepcost: usize,
}

unsafe extern "C" {
    fn mallinfo2() -> MallInfo2;
}

/// Bytes in use: small blocks in the arenas plus mmapped large blocks.
pub fn in_use() -> isize {
    // SAFETY: a plain glibc query without arguments.
    let m = unsafe { mallinfo2() };
    (m.uordblks + m.hblkhd) as isize
}
