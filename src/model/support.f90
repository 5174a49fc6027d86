!> What the support of a rod end holds (issue 26 items 2 and 3), resolved once from its &bc for
!> every formulation: the directions of the end's position that are held and whether its
!> rotation is (the Dirichlet conditions of methods/ph_director_3d.md §2.9 on a subset of the
!> end node's coordinates; se3_pg's r in inertial coordinates, methods/se3_petrov_galerkin.md
!> §5.1). Every kind that holds something is one such hold:
!> - 'clamped' and 'driven': the whole position and the rotation (a driven end's held values
!>   move in time; the formulation moves them);
!> - 'pinned': the whole position;
!> - 'sliding' along a: the position across a (P = I - a a^T / |a|^2) and the rotation;
!> - 'held' with `hold` naming some of x, y, z and 'rotation' or 'twist': those coordinates of
!>   the position (inertial axes) and, with 'rotation', the rotation ('x', 'y', 'z' = pinned,
!>   'x', 'y', 'z', 'rotation' = clamped, 'y', 'z', 'rotation' = sliding along x, 'z' = a
!>   roller on the plane z = z_0); with 'twist', the rotation about the end's axis alone, the
!>   end free to bend (the end of a shaft in a ball joint that does not let it turn about its
!>   axis: 'x', 'y', 'z', 'twist' holds the rigid twist of Greenhill's shaft, docs/theory/
!>   modes.md);
!> - 'free' and 'body' nothing.
!> A formulation that holds by eliminating coordinates maps the hold to them: the 3D ones
!> (ph_director, se3_pg) through held_coordinates (position coordinates in inertial axes), the
!> planar ones through rs_model_planarity's planar_held. The twist alone is no coordinate of
!> either: held_coordinates refuses it (ok = false, twist_hold_refusal says why), and a
!> formulation that holds it (se3_pg: one component of the end's rotation vector) maps it
!> itself; a formulation's capability row says whether it does (held_twist), so
!> --check-input refuses it before. The held values are those of the
!> reference configuration; a held coordinate does no work, so the energy balances need
!> nothing booked for it.
module rs_model_support
    use rs_core_kinds, only: rk
    use rs_core_strings, only: vector_text
    use rs_model_scene, only: bc_input_t, unset_real
    implicit none
    private

    public :: end_hold, held_coordinates, held_names, mask_names, hold_list, &
        coordinate_hold_refusal, twist_hold_refusal

    !> The names a `hold` entry may take (&bc kind = 'held'), in mask order, then 'twist'.
    character(len=*), parameter, public :: hold_entry_names = 'x|y|z|rotation|twist'

    !> What an end's support holds: its position along the range of the orthogonal projector
    !> `position` (P (phi - phi_ref) = 0: the identity for a pin, 0 for a free end) and, if
    !> `rotation`, its whole rotation; if `twist` (and not `rotation`), its rotation about its
    !> axis (the reference tangent d3) and not the two bending rotations.
    type, public :: end_hold_t
        real(rk) :: position(3, 3) = 0.0_rk
        logical :: rotation = .false.
        logical :: twist = .false.
    end type end_hold_t

    !> Entries of a projector that count as 0 or 1 (a coordinate held or free).
    real(rk), parameter :: tolerance = 1.0e-12_rk

contains

    !> The hold of a support (module header); a 'sliding' end without its axis (the input check
    !> refuses it) holds the rotation only.
    pure function end_hold(bc) result(hold)
        type(bc_input_t), intent(in) :: bc
        type(end_hold_t) :: hold
        real(rk) :: a(3)
        integer :: i
        select case (trim(bc%kind))
        case ('clamped', 'driven')
            hold%position = identity()
            hold%rotation = .true.
        case ('pinned')
            hold%position = identity()
        case ('sliding')
            hold%rotation = .true.
            if (any(bc%axis == unset_real) .or. all(bc%axis == 0.0_rk)) return
            a = bc%axis / norm2(bc%axis)
            hold%position = identity() - spread(a, 2, 3) * spread(a, 1, 3)
        case ('held')
            do i = 1, size(bc%hold)
                select case (trim(bc%hold(i)))
                case ('x')
                    hold%position(1, 1) = 1.0_rk
                case ('y')
                    hold%position(2, 2) = 1.0_rk
                case ('z')
                    hold%position(3, 3) = 1.0_rk
                case ('rotation')
                    hold%rotation = .true.
                case ('twist')
                    hold%twist = .true.
                end select
            end do
            ! The whole rotation includes its twist (the input check refuses both named).
            if (hold%rotation) hold%twist = .false.
        end select
    end function end_hold

    !> The hold as held coordinates of a formulation that holds the position's inertial
    !> coordinates and the rotation as a whole: mask = (x, y, z, then the rotation three times,
    !> e.g. se3_pg's rotation vector); `ok` is false when the held directions are not coordinate
    !> axes (a slide along an oblique axis), which such a formulation cannot hold by
    !> elimination, and when the twist alone is held (no coordinate of such a formulation;
    !> se3_pg maps it itself, twist_hold_refusal for the others).
    pure subroutine held_coordinates(hold, mask, ok)
        type(end_hold_t), intent(in) :: hold
        logical, intent(out) :: mask(6)
        logical, intent(out) :: ok
        real(rk) :: diagonal(3, 3)
        integer :: i
        diagonal = 0.0_rk
        do i = 1, 3
            mask(i) = hold%position(i, i) > 0.5_rk
            if (mask(i)) diagonal(i, i) = 1.0_rk
        end do
        mask(4:6) = hold%rotation
        ok = all(abs(hold%position - diagonal) <= tolerance) .and. .not. hold%twist
    end subroutine held_coordinates

    !> The held coordinates of a mask (held_coordinates, or se3_pg's with the twist: one of the
    !> three rotation entries) as text, e.g. 'x, z, rotation', 'x, y, z, twist'; 'none'.
    pure function held_names(mask) result(text)
        logical, intent(in) :: mask(6)
        character(len=:), allocatable :: text
        text = mask_names([mask(1:3), all(mask(4:6)), any(mask(4:6)) .and. .not. all(mask(4:6))], &
            [character(len=8) :: 'x', 'y', 'z', 'rotation', 'twist'])
    end function held_names

    !> The names whose mask entry is true, separated by commas; 'none' if there are none (the
    !> held coordinates of a formulation's own, e.g. the planar x, y, theta).
    pure function mask_names(mask, names) result(text)
        logical, intent(in) :: mask(:)
        character(len=*), intent(in) :: names(:)
        character(len=:), allocatable :: text
        integer :: i
        text = ''
        do i = 1, size(mask)
            if (.not. mask(i)) cycle
            if (len(text) > 0) text = text // ', '
            text = text // trim(names(i))
        end do
        if (len(text) == 0) text = 'none'
    end function mask_names

    !> The entries of a held end's `hold`, quoted and separated by commas (for messages).
    pure function hold_list(bc) result(text)
        type(bc_input_t), intent(in) :: bc
        character(len=:), allocatable :: text
        integer :: i
        text = ''
        do i = 1, size(bc%hold)
            if (len_trim(bc%hold(i)) == 0) cycle
            if (len(text) > 0) text = text // ', '
            text = text // '''' // trim(bc%hold(i)) // ''''
        end do
    end function hold_list

    !> Why `formulation`, which holds the inertial coordinates named `coordinates` (e.g. 'r'),
    !> cannot hold the end of rod `rod` supported by `bc` (held_coordinates gave ok = false:
    !> a slide along an oblique axis, or the twist alone).
    pure function coordinate_hold_refusal(rod, formulation, coordinates, bc) result(message)
        character(len=*), intent(in) :: rod, formulation, coordinates
        type(bc_input_t), intent(in) :: bc
        character(len=:), allocatable :: message
        type(end_hold_t) :: hold
        hold = end_hold(bc)
        if (hold%twist) then
            message = twist_hold_refusal(rod, formulation)
            return
        end if
        message = 'rod ''' // rod // ''': ' // formulation // ' holds the coordinates of ' // &
            coordinates // ', so a sliding end''s axis must be a coordinate axis (x, y or z); ' // &
            'axis = (' // vector_text(bc%axis) // ')'
    end function coordinate_hold_refusal

    !> Why `formulation` cannot hold the end of rod `rod` whose &bc holds the twist alone (a
    !> formulation whose capability row has no held_twist).
    pure function twist_hold_refusal(rod, formulation) result(message)
        character(len=*), intent(in) :: rod, formulation
        character(len=:), allocatable :: message
        message = 'rod ''' // rod // ''': ' // formulation // ' cannot hold the twist of an ' // &
            'end alone (hold = ''twist''); it holds the whole rotation or none ' // &
            '(docs/user/capabilities.md)'
    end function twist_hold_refusal


    pure function identity() result(a)
        real(rk) :: a(3, 3)
        integer :: i
        a = 0.0_rk
        do i = 1, 3
            a(i, i) = 1.0_rk
        end do
    end function identity

end module rs_model_support
