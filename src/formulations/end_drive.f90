!> A rod end driven by its pose (&bc kind = 'driven' of a formulation whose capability row has
!> drive = 'pose': se3_pg, ph_director): the end's reference position moved by f(t)
!> displacement and its reference frame turned by Exp(f(t) rotation) about that position
!> (inertial components, active rotations as rs_math_so3), f the &bc time function with
!> f(0) = 0 (the input check), so the end starts at its reference pose. Both formulations
!> build their drives from this one type and read the prescribed pose from it.
!> The prescribed pose is a Dirichlet condition on the end node's unknowns (methods/
!> ph_director_3d.md §2.9; methods/se3_petrov_galerkin.md §5.1), the superimposed rotation of
!> methods/se3_petrov_galerkin.md §10.3 its objectivity test.
#include "rs_macros.h"
module rs_formulations_end_drive
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t, set_error
    use rs_math_so3, only: exp_so3
    use rs_model_scene, only: bc_input_t
    use rs_model_time_function, only: time_function_t, time_function_from_bc
    implicit none
    private

    public :: end_drive_init

    !> One driven end: its node, the motion at f = 1 and the reference pose.
    type, public :: end_drive_t
        integer :: node = 0
        real(rk) :: displacement(3) = 0.0_rk
        real(rk) :: rotation(3) = 0.0_rk
        real(rk) :: position(3) = 0.0_rk
        !> Reference frame: columns are the end's frame vectors in inertial components
        !> (ph_director: the directors d1, d2, d3; se3_pg: A0 of its K basis).
        real(rk) :: frame(3, 3) = 0.0_rk
        type(time_function_t) :: factor
    contains
        !> The prescribed position and frame at time t.
        procedure :: pose => end_drive_pose
    end type end_drive_t

contains

    !> The drive of `bc` on node `node`, whose reference position and frame are given.
    subroutine end_drive_init(drive, bc, node, position, frame, err)
        type(end_drive_t), intent(out) :: drive
        type(bc_input_t), intent(in) :: bc
        integer, intent(in) :: node
        real(rk), intent(in) :: position(3), frame(3, 3)
        type(error_t), allocatable, intent(out) :: err
        call time_function_from_bc(bc, drive%factor, err)
        RS_RETURN_IF_ERROR(err)
        drive%node = node
        drive%displacement = bc%displacement
        drive%rotation = bc%rotation
        drive%position = position
        drive%frame = frame
    end subroutine end_drive_init

    pure subroutine end_drive_pose(this, t, position, frame)
        class(end_drive_t), intent(in) :: this
        real(rk), intent(in) :: t
        real(rk), intent(out) :: position(3), frame(3, 3)
        real(rk) :: f
        f = this%factor%value(t)
        position = this%position + f * this%displacement
        frame = matmul(exp_so3(f * this%rotation), this%frame)
    end subroutine end_drive_pose

end module rs_formulations_end_drive
