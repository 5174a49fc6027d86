!> The --check-input plan of an se3_strand rod (DESIGN.md §4; rs_formulations_plan prints it):
!> the staggered grid, the unknowns, the one linear solve per step, supports, loads, damping and
!> what is skipped.
module rs_se3_strand_plan
    use rs_core_strings, only: str, str_significant
    use rs_model_scene, only: scene_t, load_applies_to, rod_is_damped
    use rs_model_damping, only: damping_plan_text
    use rs_model_rod_geometry, only: centreline_text
    implicit none
    private

    public :: se3_strand_plan_lines

contains

    !> '!' lines (each ending in a new line) of rod `i`.
    function se3_strand_plan_lines(scene, i) result(lines)
        type(scene_t), intent(in) :: scene
        integer, intent(in) :: i
        character(len=:), allocatable :: lines
        character(len=:), allocatable :: supports, damping, skipped
        integer :: j, n, n_follower, n_dead
        associate (rod => scene%rods(i))
            n = rod%n_elements
            lines = ''
            call add('grid: ' // str(n) // ' segments, staggered (methods/se3_strands.md §3.1): ' // &
                'momenta P at ' // str(n + 1) // ' nodes, stresses Sigma at ' // str(n) // &
                ' segment midpoints + 2 ghosts; degree and n_gauss do not apply')
            call add('geometry: ' // centreline_text(rod, trim(scene%run%units)))
            if (rod%prestressed) then
                call add('reference: prestressed: the stress-free shape is straight; the rod ' // &
                    'starts with the elastic stresses of its initial geometry')
            else
                call add('reference: stress-free initial geometry (the SE(3) logarithm of each ' // &
                    'segment''s relative nodal pose over its length is its relaxed strain)')
            end if
            call add('unknowns: 6 x (2 N + 3) = ' // str(6 * (2 * n + 3)) // ', interleaved ' // &
                '(Sigma_-1, P_0, Sigma_0, P_1, ...): block tridiagonal, half bandwidth 11')
            call add('step: semi-implicit (eqs. 11-15), coefficients frozen at t_n, one sparse ' // &
                'linear solve per step (SNES ksponly, PETSc LU), no Newton loop; first order in time')
            supports = ''
            do j = 1, size(scene%bcs)
                if (trim(scene%bcs(j)%rod) /= trim(rod%name)) cycle
                supports = supports // ' ' // trim(scene%bcs(j)%end) // ' ' // trim(scene%bcs(j)%kind)
            end do
            if (.not. any(scene%bcs%rod == rod%name .and. scene%bcs%end == 'start' .and. &
                scene%bcs%kind /= 'free')) supports = supports // ' start free (no stress at ' // &
                's = 0, its half cell balanced like the end''s)'
            call add('supports:' // supports // ' (motion or no stress prescribed at s = 0, ' // &
                'stress at s = L)')
            n_follower = 0
            n_dead = 0
            do j = 1, size(scene%loads)
                if (.not. load_applies_to(scene%loads(j), rod%name)) cycle
                if (trim(scene%loads(j)%frame) == 'follower') then
                    n_follower = n_follower + 1
                else
                    n_dead = n_dead + 1
                end if
            end do
            call add('loads: ' // str(n_dead) // ' dead (turned with the sections, linearized ' // &
                'implicitly), ' // str(n_follower) // ' follower')
            damping = ''
            if (rod%external_damping > 0.0) damping = damping // ' external ' // &
                str_significant(rod%external_damping, 4)
            if (rod%internal_damping > 0.0) damping = damping // ' internal (paper''s law) ' // &
                str_significant(rod%internal_damping, 4)
            if (rod_is_damped(rod)) damping = damping // ' ' // damping_plan_text(rod)
            if (len(damping) == 0) damping = ' none (the scheme''s own numerical dissipation only)'
            call add('damping:' // damping)
            if (scene%time%relaxation) call add('relaxation: stop when the kinetic energy < ' // &
                str_significant(scene%time%kinetic_energy_tol, 3) // ' J')
            skipped = 'skipped: Newton, constraints, Maxwell branches, actuators, joints'
            if (n_dead == 0) skipped = skipped // ', pose reconstruction per step (no dead loads)'
            call add(skipped)
        end associate
    contains
        subroutine add(line)
            character(len=*), intent(in) :: line
            lines = lines // '!     ' // line // new_line('a')
        end subroutine add
    end function se3_strand_plan_lines

end module rs_se3_strand_plan
