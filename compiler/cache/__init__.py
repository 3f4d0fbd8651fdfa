"""The compilation cache (docs/cache.md): compiled models and C libraries kept between runs, keyed
by a hash of every source a compile read, its options and the compiler itself, so that a second
`dyadc simulate` of an unchanged model skips parsing, flattening and structural analysis and never
imports sympy or lark. Modules: store (folder, sealed files), keys (what a compile depends on),
recording (a library that notes what it reads), models (entries of compiled models), native (a
model put on compiled C before its first run, or the VM: codegen_choice), c_code and c_libraries
(building and keeping the C libraries), contents (`dyadc cache info|clear`)."""
