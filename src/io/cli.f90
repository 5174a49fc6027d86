!> The command line of `rodsolve` (README.md, docs/user/running.md):
!>
!>     rodsolve [--quiet] SCENE.nml [PETSc options]
!>     rodsolve --check-input SCENE.nml
!>     rodsolve --merge SWEEP.nml
!>     rodsolve --help | --version | --input-reference | --capabilities
!>
!> rodsolve's own flags start with "--"; every other argument that starts with "-" begins a
!> PETSc option (with the arguments up to the next "-" as its value) and is handed to
!> PetscInitialize. The scene is the first argument that is neither.
module rs_io_cli
    implicit none
    private

    public :: cli_t, parse_command_line, usage_text

    integer, parameter :: arg_len = 4096

    !> What the command line asks for.
    type :: cli_t
        !> 'run', 'check', 'merge', 'help', 'version', 'reference' or 'capabilities'.
        character(len=16) :: action = 'run'
        character(len=:), allocatable :: scene_file
        logical :: quiet = .false.
        character(len=:), allocatable :: program
        !> Arguments for PETSc, in order.
        character(len=arg_len), allocatable :: petsc_args(:)
        !> Problems with the command line ('' if none).
        character(len=:), allocatable :: error
    end type cli_t

contains

    !> Parse `args` (without the program name; from get_command_argument in the main program).
    pure function parse_command_line(program, args) result(cli)
        character(len=*), intent(in) :: program
        character(len=*), intent(in) :: args(:)
        type(cli_t) :: cli
        integer :: i
        logical :: in_petsc_option
        character(len=:), allocatable :: arg

        cli%program = trim(program)
        cli%scene_file = ''
        cli%error = ''
        allocate(cli%petsc_args(0))
        in_petsc_option = .false.
        do i = 1, size(args)
            arg = trim(args(i))
            if (len(arg) >= 2) then
                if (arg(1:2) == '--') then
                    in_petsc_option = .false.
                    select case (arg)
                    case ('--help')
                        cli%action = 'help'
                    case ('--version')
                        cli%action = 'version'
                    case ('--input-reference')
                        cli%action = 'reference'
                    case ('--capabilities')
                        cli%action = 'capabilities'
                    case ('--check-input')
                        if (cli%action == 'run') cli%action = 'check'
                    case ('--merge')
                        if (cli%action == 'run') cli%action = 'merge'
                    case ('--quiet')
                        cli%quiet = .true.
                    case default
                        call add_error(cli, 'unknown flag ' // arg // ' (rodsolve --help lists the flags)')
                    end select
                    cycle
                end if
            end if
            if (arg == '-h') then
                cli%action = 'help'
            else if (arg(1:min(1, len(arg))) == '-') then
                cli%petsc_args = [character(len=arg_len) :: cli%petsc_args, args(i)]
                in_petsc_option = .true.
            else if (in_petsc_option) then
                cli%petsc_args = [character(len=arg_len) :: cli%petsc_args, args(i)]
            else if (len(cli%scene_file) == 0) then
                cli%scene_file = arg
            else
                call add_error(cli, 'a second scene file "' // arg // '" (one scene per run; ' // &
                    'PETSc options start with "-")')
            end if
        end do
        if ((cli%action == 'run' .or. cli%action == 'check' .or. cli%action == 'merge') .and. &
                len(cli%scene_file) == 0 .and. &
                len(cli%error) == 0) call add_error(cli, 'no scene file given')
    end function parse_command_line

    pure subroutine add_error(cli, message)
        type(cli_t), intent(inout) :: cli
        character(len=*), intent(in) :: message
        if (len(cli%error) > 0) cli%error = cli%error // new_line('a')
        cli%error = cli%error // 'rodsolve: ' // message
    end subroutine add_error

    !> The text of `rodsolve --help`.
    pure function usage_text() result(text)
        character(len=:), allocatable :: text
        character(len=*), parameter :: nl = new_line('a')
        text = 'usage: mpirun -np N rodsolve [--quiet] SCENE.nml [PETSc options]' // nl // &
            '       rodsolve --check-input SCENE.nml' // nl // &
            '       rodsolve --merge SWEEP.nml' // nl // &
            '       rodsolve --help | --version | --input-reference | --capabilities' // nl // nl // &
            'Simulates Cosserat rods described by a namelist scene file (docs/user/input.md).' // nl // nl // &
            '  --check-input      read and validate SCENE.nml, print the resolved scene; run nothing' // nl // &
            '  --merge            rebuild the result file of a killed sweep from its finished' // nl // &
            '                     members (the files under OUTPUT.h5.members/)' // nl // &
            '  --quiet            print warnings and errors only' // nl // &
            '  --version          print the version of rodsolve and of the libraries it uses' // nl // &
            '  --input-reference  print the reference of every input group and variable' // nl // &
            '  --capabilities     print what each formulation can do (docs/user/capabilities.md)' // nl // &
            '  --help, -h         print this text' // nl // nl // &
            'Any argument starting with a single "-" is a PETSc option, e.g. -snes_monitor or' // nl // &
            '-ksp_type gmres; they override the scene''s petsc_options.' // nl // &
            'Exit status: 0 success, 1 run failure, 2 invalid command line or input.'
    end function usage_text

end module rs_io_cli
