!> The damping a rod asks for (&rod kelvin_voigt_time, drag, angular_drag; issue 26 item 1),
!> as the formulations read it: the Kelvin-Voigt times in a formulation's own order of stress
!> components and the text of the --check-input plan. The physics and its discrete dissipation
!> are in docs/theory/damping.md; each formulation applies it in its own kernels.
module rs_model_damping
    use rs_core_kinds, only: rk
    use rs_core_strings, only: str_significant, append_joined
    use rs_model_scene, only: rod_input_t
    implicit none
    private

    public :: damping_plan_text

    !> Positions of EA, GA1, GA2, EI1, EI2, GJ in &rod kelvin_voigt_time.
    integer, parameter, public :: kv_axial = 1, kv_shear1 = 2, kv_shear2 = 3, kv_bend1 = 4, &
        kv_bend2 = 5, kv_torsion = 6

contains

    !> The plan's words for the rod's damping ('none' when it has none), e.g.
    !> 'Kelvin-Voigt 0.001 s (every component); drag 0.5 N s/m^2'.
    function damping_plan_text(rod) result(text)
        type(rod_input_t), intent(in) :: rod
        character(len=:), allocatable :: text
        integer :: i
        text = ''
        if (any(rod%kelvin_voigt_time > 0.0_rk)) then
            if (all(rod%kelvin_voigt_time == rod%kelvin_voigt_time(1))) then
                text = 'Kelvin-Voigt ' // str_significant(rod%kelvin_voigt_time(1), 4) // &
                    ' s (every component)'
            else
                text = 'Kelvin-Voigt (EA, GA1, GA2, EI1, EI2, GJ) ' // &
                    str_significant(rod%kelvin_voigt_time(1), 4)
                do i = 2, 6
                    text = text // ', ' // str_significant(rod%kelvin_voigt_time(i), 4)
                end do
                text = text // ' s'
            end if
        end if
        if (rod%drag > 0.0_rk) call append_joined(text, '; ', 'drag ' // &
            str_significant(rod%drag, 4) // ' N s/m^2')
        if (rod%angular_drag > 0.0_rk) call append_joined(text, '; ', 'angular drag ' // &
            str_significant(rod%angular_drag, 4) // ' N s')
        if (len(text) == 0) text = 'none'
    end function damping_plan_text

end module rs_model_damping
