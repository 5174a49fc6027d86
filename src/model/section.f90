!> Cross-section properties of the shapes a scene may name (DESIGN.md §1): area, second moments
!> about the directors d1 and d2, and the torsion constant, either the polar moment
!> (I1 + I2, the value the seeds use, e.g. seed 004's 45-degree bend) or Saint-Venant's.
!> Pure functions of the dimensions.
module rs_model_section
    use rs_core_kinds, only: rk, pi
    implicit none
    private

    public :: section_properties_t, circle_section, tube_section, rectangle_section, &
        section_values, shaped_section

    !> Geometric properties of a section; I1 about d1, I2 about d2.
    type :: section_properties_t
        real(rk) :: area = 0.0_rk
        real(rk) :: i1 = 0.0_rk
        real(rk) :: i2 = 0.0_rk
        real(rk) :: polar = 0.0_rk
        real(rk) :: saint_venant = 0.0_rk
    end type section_properties_t

contains

    !> Solid circle of radius r (Saint-Venant's torsion constant equals the polar moment).
    pure function circle_section(r) result(s)
        real(rk), intent(in) :: r
        type(section_properties_t) :: s
        s = tube_section(r, 0.0_rk)
    end function circle_section

    !> Circular tube of outer radius r_out and inner radius r_in.
    pure function tube_section(r_out, r_in) result(s)
        real(rk), intent(in) :: r_out, r_in
        type(section_properties_t) :: s
        s%area = pi * (r_out**2 - r_in**2)
        s%i1 = pi * (r_out**4 - r_in**4) / 4.0_rk
        s%i2 = s%i1
        s%polar = s%i1 + s%i2
        s%saint_venant = s%polar
    end function tube_section

    !> Rectangle with side `width` along d1 and `height` along d2.
    !> Saint-Venant's constant from the series solution of the Prandtl stress function
    !> (Timoshenko & Goodier, Theory of Elasticity, §109):
    !> J = a b^3 / 3 (1 - 192 b / (pi^5 a) sum_{n odd} tanh(n pi a / (2 b)) / n^5), a >= b.
    pure function rectangle_section(width, height) result(s)
        real(rk), intent(in) :: width, height
        type(section_properties_t) :: s
        real(rk) :: a, b, series, term
        integer :: n
        s%area = width * height
        s%i1 = width * height**3 / 12.0_rk
        s%i2 = height * width**3 / 12.0_rk
        s%polar = s%i1 + s%i2
        a = max(width, height)
        b = min(width, height)
        series = 0.0_rk
        n = 1
        do
            term = tanh(real(n, rk) * pi * a / (2.0_rk * b)) / real(n, rk)**5
            series = series + term
            if (term < 1.0e-17_rk * series) exit
            n = n + 2
        end do
        s%saint_venant = a * b**3 / 3.0_rk * (1.0_rk - 192.0_rk * b / (pi**5 * a) * series)
    end function rectangle_section

    !> The section of shape `kind` ('circle', 'tube' or 'rectangle') with dims = (radius,
    !> inner_radius, width, height); the entries a shape does not use are ignored.
    pure function shaped_section(kind, dims) result(s)
        character(len=*), intent(in) :: kind
        real(rk), intent(in) :: dims(4)
        type(section_properties_t) :: s
        select case (kind)
        case ('circle')
            s = circle_section(dims(1))
        case ('tube')
            s = tube_section(dims(1), dims(2))
        case ('rectangle')
            s = rectangle_section(dims(3), dims(4))
        end select
    end function shaped_section

    !> EA, GA1, GA2, EI1, EI2, GJ, rhoA, rhoI1, rhoI2 of section `s` of a material: Young's
    !> modulus E, shear modulus G, density, shear factor k (GA = k G A) and the torsion constant
    !> (Saint-Venant's if `saint_venant`, else the polar moment).
    pure function section_values(s, e, g, density, shear_factor, saint_venant) result(values)
        type(section_properties_t), intent(in) :: s
        real(rk), intent(in) :: e, g, density, shear_factor
        logical, intent(in) :: saint_venant
        real(rk) :: values(9)
        real(rk) :: torsion
        torsion = s%polar
        if (saint_venant) torsion = s%saint_venant
        values = [e * s%area, shear_factor * g * s%area, shear_factor * g * s%area, e * s%i1, &
            e * s%i2, g * torsion, density * s%area, density * s%i1, density * s%i2]
    end function section_values

end module rs_model_section
