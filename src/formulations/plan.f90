!> The plan of a resolved, checked scene (DESIGN.md §4, `rodsolve --check-input`): what runs and
!> what is skipped, as namelist comments ('!' lines) so that the output of --check-input stays a
!> scene that reads back to itself. Scene-wide: time steps, output, units, how the rods are
!> dealt to the ranks; per rod: its formulation and why (for 'auto': the plane the rods lie in,
!> or why they are 3D), and what that formulation says about it (rs_ph_director_plan,
!> rs_ph_planar_plan). Adding a formulation adds its case here, as in the factory.
module rs_formulations_plan
    use rs_core_kinds, only: rk
    use rs_core_error, only: error_t
    use rs_core_strings, only: str
    use rs_model_scene, only: scene_t
    use rs_model_units, only: unit_in_system
    use rs_ph_director_plan, only: ph_director_plan_lines
    use rs_ph_planar_plan, only: ph_planar_plan_lines
    use rs_se3_pg_plan, only: se3_pg_plan_lines
    use rs_se3_strand_plan, only: se3_strand_plan_lines
    use rs_model_coupling, only: coupled_systems
    implicit none
    private

    public :: scene_plan_text, plan_step_count

    !> First line of the plan; a reader of --check-input output finds the plan by it.
    character(len=*), parameter, public :: plan_header = &
        '! plan: what runs and what is skipped (DESIGN.md §4)'

contains

    !> The plan of `scene` for a run on `n_ranks` ranks; one '!' line per item, each ending in a
    !> new line. A rod that cannot be built says why in its place.
    function scene_plan_text(scene, n_ranks) result(text)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: n_ranks
        character(len=:), allocatable :: text, lines, units, why
        type(error_t), allocatable :: err
        integer :: i, n_steps, n_records, rank
        integer, allocatable :: system_of(:), first(:), members(:)

        units = trim(scene%run%units)
        n_steps = plan_step_count(scene)
        n_records = 1 + n_steps / scene%output%stride
        if (mod(n_steps, scene%output%stride) /= 0) n_records = n_records + 1
        text = plan_header // new_line('a')
        if (scene%time%quasistatic) then
            call add('time: quasistatic, ' // str(n_steps) // ' midpoint load step(s) of ' // &
                str(scene%time%dt) // ' to the load factor t_end = ' // str(scene%time%t_end) // &
                ', then one endpoint equilibrium solve (ph_director rods)')
        else
            call add('time: ' // str(n_steps) // ' ' // trim(scene%time%scheme) // ' step(s) of dt = ' // &
                str(scene%time%dt) // ' ' // unit_in_system('s', units) // ' to t_end = ' // &
                str(scene%time%t_end) // ' ' // unit_in_system('s', units) // &
                ' (halved up to ' // str(scene%solver%max_cutbacks) // ' times on Newton failure)')
        end if
        call add('Newton: stops at the scaled residual norm ' // str(scene%solver%newton_atol) // &
            ', at most ' // str(scene%solver%max_newton) // ' iterations; LU per system: MUMPS, ' // &
            'or PETSc''s own LU where the Jacobian needs no pivoting (planar dynamics)')
        call add('output: ' // trim(scene%output%path) // ': fields ''' // trim(scene%output%fields) // &
            ''', ' // str(n_records) // ' record(s) (t = 0, every ' // str(scene%output%stride) // &
            ' step(s) and the last), flushed every ' // str(scene%output%flush_every) // &
            ' step(s), XDMF sidecar ' // trim(merge('yes', 'no ', scene%output%xdmf)))
        call add('units: ''' // units // ''' (length ' // unit_in_system('m', units) // ', mass ' // &
            unit_in_system('kg', units) // ', time ' // unit_in_system('s', units) // ', force ' // &
            unit_in_system('N', units) // ', stress ' // unit_in_system('Pa', units) // '); the ' // &
            'numbers are used as given')
        ! Rods joined by &joint groups are one system, solved together (rs_model_coupling).
        call coupled_systems(scene, system_of, first, members)
        call add('ranks: ' // str(size(scene%rods)) // ' rod(s) in ' // str(size(first) - 1) // &
            ' system(s) (a rod, or rods joined by &joint) on ' // str(n_ranks) // ' rank(s), ' // &
            'dealt round robin (system k on rank mod(k - 1, ' // str(n_ranks) // ')), each solved on ' // &
            'its own (no communication in the time loop)')
        do i = 1, size(scene%rods)
            rank = mod(system_of(i) - 1, n_ranks)
            associate (rod => scene%rods(i))
                select case (trim(rod%formulation_origin))
                case ('default')
                    why = 'from &run formulation_default'
                case ('auto')
                    why = 'auto: ' // trim(rod%formulation_reason)
                case default
                    why = 'given in &rod'
                end select
                call add('rod ''' // trim(rod%name) // ''' on rank ' // str(rank) // ': ' // &
                    trim(rod%formulation) // ' (' // why // ')')
                select case (trim(rod%formulation))
                case ('ph_director')
                    call ph_director_plan_lines(scene, i, lines, err)
                    if (allocated(err)) lines = '!     cannot be built: ' // err%describe() // new_line('a')
                case ('ph_planar', 'cl_em_planar')
                    call ph_planar_plan_lines(scene, i, lines)
                case ('se3_pg')
                    lines = se3_pg_plan_lines(scene, i)
                case ('se3_strand')
                    lines = se3_strand_plan_lines(scene, i)
                case default
                    lines = '!     formulation not available in this version' // new_line('a')
                end select
                text = text // lines
            end associate
        end do
    contains
        subroutine add(line)
            character(len=*), intent(in) :: line
            text = text // '!   ' // line // new_line('a')
        end subroutine add
    end function scene_plan_text

    !> Number of steps of the scene's time grid, max(1, ceiling(t_end / dt)) as the run takes
    !> them (the last one may be shorter).
    pure integer function plan_step_count(scene) result(n)
        type(scene_t), intent(in) :: scene
        n = max(1, ceiling(scene%time%t_end / scene%time%dt - 1.0e-9_rk))
    end function plan_step_count

end module rs_formulations_plan
