// The translation unit that carries the command lines' CLI11 precompiled header (CMakeLists.txt).
