!> A tie of ph_director nodes as the system layer sees it (rs_formulations_formulation's
!> node_tie_t, issue 22): the constraint rows of a joint between two nodes, or of a rod end
!> tied to a rigid end plate, on z = [q_a; q_b], q = (phi, d1, d2, d3) (24 entries; a plate
!> ties one node and the b-part of z is zero). The rows and their derivatives are the pure
!> kernels of rs_ph_director_tie (ph_director_tie.f90, where the rows, what they keep and how
!> the midpoint step uses them are stated); this type only holds the rows of one tie and, for a
!> plate, the reference coordinates of its node, so that the system can move the plate.
module rs_ph_director_node_tie
    use rs_core_kinds, only: rk
    use rs_formulations_formulation, only: node_tie_t
    use rs_ph_director_tie, only: ph_director_tie_t, ph_director_joint_tie, &
        ph_director_plate_tie, ph_director_tie_value, ph_director_tie_gradient, &
        ph_director_tie_hessian, ph_director_tie_size
    implicit none
    private

    public :: ph_director_node_tie

    !> A joint ('rigid', 'spherical', 'revolute') or a plate tie of ph_director nodes.
    type, extends(node_tie_t), public :: ph_director_node_tie_t
        !> The tie's quadratic rows in the current pose (a joint's never change).
        type(ph_director_tie_t) :: rows
        !> A one-node tie to an end plate, which `place` moves.
        logical :: plate = .false.
        !> The plate-tied node's reference coordinates (the plate's reference pose holds them).
        real(rk) :: q_ref(12) = 0.0_rk
    contains
        procedure :: place => node_tie_place
        procedure :: value => node_tie_value
        procedure :: gradient => node_tie_gradient
        procedure :: force_hessian => node_tie_hessian
    end type ph_director_node_tie_t

contains

    !> The tie of `kind` on nodes of reference coordinates q_a, q_b (12 each): a joint of
    !> ph_director_joint_tie ('rigid', 'spherical', 'revolute'; `axis` the revolute hinge), or
    !> with 'plate' the tie of node a to its plate in the plate's reference pose (q_b and axis
    !> unused). Any other kind leaves `tie` unallocated.
    subroutine ph_director_node_tie(kind, q_a, q_b, axis, tie)
        character(len=*), intent(in) :: kind
        real(rk), intent(in) :: q_a(:), q_b(:), axis(3)
        class(node_tie_t), allocatable, intent(out) :: tie
        type(ph_director_node_tie_t) :: made
        real(rk), parameter :: zero(3) = 0.0_rk
        select case (trim(kind))
        case ('rigid', 'spherical', 'revolute')
            made%rows = ph_director_joint_tie(trim(kind), q_a(1:12), q_b(1:12), axis)
        case ('plate')
            made%plate = .true.
            made%q_ref = q_a(1:12)
            made%rows = ph_director_plate_tie(made%q_ref, zero, zero, zero)
        case default
            return
        end select
        made%n = made%rows%n
        made%n_coordinates = 12
        allocate(tie, source=made)
    end subroutine ph_director_node_tie

    !> A plate's tie in the pose turned by exp(rotation) about `centre` and moved by
    !> `displacement` from its reference; a joint does not move.
    pure subroutine node_tie_place(this, centre, displacement, rotation)
        class(ph_director_node_tie_t), intent(inout) :: this
        real(rk), intent(in) :: centre(3), displacement(3), rotation(3)
        if (.not. this%plate) return
        this%rows = ph_director_plate_tie(this%q_ref, centre, displacement, rotation)
    end subroutine node_tie_place

    pure subroutine node_tie_value(this, z, g)
        class(ph_director_node_tie_t), intent(in) :: this
        real(rk), intent(in) :: z(:)
        real(rk), intent(out) :: g(:)
        g(1:this%n) = ph_director_tie_value(this%rows, z(1:ph_director_tie_size))
    end subroutine node_tie_value

    pure subroutine node_tie_gradient(this, z, gradient)
        class(ph_director_node_tie_t), intent(in) :: this
        real(rk), intent(in) :: z(:)
        real(rk), intent(out) :: gradient(:, :)
        gradient(1:this%n, 1:ph_director_tie_size) = &
            ph_director_tie_gradient(this%rows, z(1:ph_director_tie_size))
    end subroutine node_tie_gradient

    !> The rows are quadratic: the Hessian does not depend on z.
    pure subroutine node_tie_hessian(this, z, lambda, hessian)
        class(ph_director_node_tie_t), intent(in) :: this
        real(rk), intent(in) :: z(:), lambda(:)
        real(rk), intent(out) :: hessian(:, :)
        hessian(1:ph_director_tie_size, 1:ph_director_tie_size) = &
            ph_director_tie_hessian(this%rows, lambda(1:this%n))
    end subroutine node_tie_hessian

end module rs_ph_director_node_tie
