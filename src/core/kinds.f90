!> Working precisions of rodsolve.
!>
!> `rk` and `ik` are the C interoperable kinds that PETSc's `PetscReal` and `PetscInt` have in the
!> build rodsolve supports (double precision reals, 32-bit indices). CMake checks that agreement
!> at configure time (cmake/RodsolveDeps.cmake), so kernels use these kinds and never include
!> PETSc (DESIGN.md §2, STYLE.md item 9).
module rs_core_kinds
    use, intrinsic :: iso_c_binding, only: c_double, c_int32_t, c_int64_t
    implicit none
    private

    !> Real kind of every floating-point quantity (PetscReal).
    integer, parameter, public :: rk = c_double
    !> Integer kind of indices handed to PETSc (PetscInt).
    integer, parameter, public :: ik = c_int32_t
    !> Integer kind of counters that may exceed 2**31 (clock ticks, byte counts).
    integer, parameter, public :: i8 = c_int64_t

    !> pi to the precision of rk.
    real(rk), parameter, public :: pi = 3.14159265358979323846264338327950288_rk
end module rs_core_kinds
