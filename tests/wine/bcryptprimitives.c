/*
 * A stand-in for Windows' bcryptprimitives.dll, for the tests under Wine only (never shipped):
 * Rust's standard library asks it for random bytes (`ProcessPrng`, in every Windows 10 and
 * later), and Debian's Wine 8.0 has no such DLL. It forwards to RtlGenRandom
 * (advapi32's SystemFunction036), which Wine has. tests/wine/prepare builds it with mingw and
 * puts it into the Wine prefix's system32.
 */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length); /* RtlGenRandom */

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T length) {
    while (length > 0) {
        ULONG n = length > 0x40000000 ? 0x40000000 : (ULONG)length;
        if (!SystemFunction036(data, n)) return FALSE;
        data += n;
        length -= n;
    }
    return TRUE;
}
