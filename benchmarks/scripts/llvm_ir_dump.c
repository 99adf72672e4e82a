/* What reaches LLVM from Mesa's llvmpipe (OpenGL) and lavapipe (Vulkan): an LD_PRELOAD shim
 * that writes every LLVM module gallivm optimizes, before and after its passes, to
 * $IRDUMP_DIR/NNNN-pre.ll and NNNN-post.ll. Release builds of Mesa ignore GALLIVM_DEBUG,
 * LP_DEBUG and NIR_DEBUG; this works on them (Mesa 22.3 with LLVM 15 calls LLVMRunPasses).
 *
 *   gcc -shared -fPIC -O2 -o /tmp/llvm_ir_dump.so benchmarks/scripts/llvm_ir_dump.c -l:libLLVM-15.so.1 -ldl
 *   mkdir -p /tmp/ir && MESA_SHADER_CACHE_DISABLE=true LD_PRELOAD=/tmp/llvm_ir_dump.so IRDUMP_DIR=/tmp/ir \
 *       python benchmarks/scripts/callgrind_frames.py seed --size 256 --frames 1
 *   grep -l '^define void @fs_variant' /tmp/ir/*-post.ll     # the fragment shaders
 *
 * MESA_SHADER_CACHE_DISABLE matters: with a warm disk cache llvmpipe loads compiled code and
 * never runs the passes. docs/performance.md ("Why the same shader was slower") reads them.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>

typedef struct LLVMOpaqueModule *LLVMModuleRef;
typedef void *LLVMErrorRef;
extern int LLVMPrintModuleToFile(LLVMModuleRef module, const char *filename, char **error);

static int counter = 0;

static void dump(LLVMModuleRef module, int number, const char *stage) {
    const char *dir = getenv("IRDUMP_DIR");
    char path[4096];
    char *error = 0;
    if (!dir)
        return;
    snprintf(path, sizeof path, "%s/%04d-%s.ll", dir, number, stage);
    LLVMPrintModuleToFile(module, path, &error);
}

LLVMErrorRef LLVMRunPasses(LLVMModuleRef module, const char *passes, void *machine, void *options) {
    static LLVMErrorRef (*real)(LLVMModuleRef, const char *, void *, void *) = 0;
    if (!real)
        real = (LLVMErrorRef(*)(LLVMModuleRef, const char *, void *, void *))dlsym(RTLD_NEXT, "LLVMRunPasses");
    int number = __sync_fetch_and_add(&counter, 1);
    dump(module, number, "pre");
    LLVMErrorRef result = real(module, passes, machine, options);
    dump(module, number, "post");
    return result;
}
