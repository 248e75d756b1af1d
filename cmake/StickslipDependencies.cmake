# Debian 12 packages (scripts/setup.sh installs them); why each one: docs/dependencies.md.
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(fmt REQUIRED)
find_package(yaml-cpp REQUIRED)
find_package(CLI11 REQUIRED)
find_package(nlohmann_json 3.11 REQUIRED)
find_package(Threads REQUIRED)

# SuiteSparse 5.x on Debian 12 ships no CMake config: find CHOLMOD/UMFPACK by hand.
find_path(SUITESPARSE_INCLUDE_DIR cholmod.h PATH_SUFFIXES suitesparse REQUIRED)
foreach(lib cholmod umfpack amd colamd camd ccolamd suitesparseconfig)
  find_library(SUITESPARSE_${lib}_LIBRARY ${lib} REQUIRED)
endforeach()
add_library(stickslip_suitesparse INTERFACE)
target_include_directories(stickslip_suitesparse SYSTEM INTERFACE ${SUITESPARSE_INCLUDE_DIR})
target_link_libraries(stickslip_suitesparse INTERFACE
  ${SUITESPARSE_cholmod_LIBRARY} ${SUITESPARSE_umfpack_LIBRARY} ${SUITESPARSE_amd_LIBRARY}
  ${SUITESPARSE_colamd_LIBRARY} ${SUITESPARSE_camd_LIBRARY} ${SUITESPARSE_ccolamd_LIBRARY}
  ${SUITESPARSE_suitesparseconfig_LIBRARY})

# Spectra is header-only (libspectra-dev, /usr/include/Spectra) and ships no CMake config.
find_path(SPECTRA_INCLUDE_DIR Spectra/SymGEigsShiftSolver.h REQUIRED)
add_library(stickslip_spectra INTERFACE)
target_include_directories(stickslip_spectra SYSTEM INTERFACE ${SPECTRA_INCLUDE_DIR})

# Gmsh C++ API (libgmsh-dev).
find_path(GMSH_INCLUDE_DIR gmsh.h REQUIRED)
find_library(GMSH_LIBRARY gmsh REQUIRED)
add_library(stickslip_gmsh INTERFACE)
target_include_directories(stickslip_gmsh SYSTEM INTERFACE ${GMSH_INCLUDE_DIR})
target_link_libraries(stickslip_gmsh INTERFACE ${GMSH_LIBRARY})

if(STICKSLIP_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(STICKSLIP_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()
