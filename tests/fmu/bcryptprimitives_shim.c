/* ProcessPrng, the one function Rust's std (1.78 and later) imports from
 * bcryptprimitives.dll for its random seeds. Windows 10 and later ship that
 * DLL; Debian's Wine 8.0 does not, so an FMU DLL does not load there. The
 * Wine test (host-tools/tests/integration/fmu_windows.rs) builds this shim
 * beside its importer, where Windows looks first; the FMU's DLL is the one in
 * the FMU, unchanged. RtlGenRandom is advapi32's SystemFunction036. */
#include <windows.h>

BOOLEAN WINAPI SystemFunction036(PVOID buffer, ULONG length);

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T len) {
    while (len > 0) {
        ULONG chunk = len > 0x10000000 ? 0x10000000 : (ULONG)len;
        if (!SystemFunction036(data, chunk)) return FALSE;
        data += chunk;
        len -= chunk;
    }
    return TRUE;
}
