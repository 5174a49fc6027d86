# Sourced by the scripts: lets Open MPI run as root (CI and containers run as root) and with
# more ranks than cores (the scripts pass --oversubscribe too).
export OMPI_ALLOW_RUN_AS_ROOT=1
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1
# One BLAS thread per rank (DESIGN.md §3): OpenBLAS serial is the Debian alternative used.
export OPENBLAS_NUM_THREADS=1
export OMP_NUM_THREADS=1
