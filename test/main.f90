!> Runs every suite (or one suite, or one test: `fpm test -- SUITE [TEST]`) and ends
!> with the line `N passed, N failed`.
program tester
  use, intrinsic :: iso_fortran_env, only: output_unit
  use testdrive, only: run_testsuite, new_testsuite, testsuite_type, select_suite, &
    run_selected, get_argument, unittest_type
  use test_spring, only: collect_spring
  use test_namelist, only: collect_namelist
  use test_table_io, only: collect_table_io
  use test_text, only: collect_text
  use test_harmonic, only: collect_harmonic
  use test_roots, only: collect_roots
  use test_stiffness, only: collect_stiffness
  use test_scene, only: collect_scene
  use test_interaction, only: collect_interaction
  use test_yade, only: collect_yade
  use test_contact, only: collect_contact
  use test_cost, only: collect_cost
  use test_double_double, only: collect_double_double
  use test_capi, only: collect_capi
  use test_app, only: collect_app
  use test_app_stiffness, only: collect_app_stiffness
  use test_progress, only: collect_progress
  use test_deck, only: collect_deck
  use test_extremes, only: collect_extremes
  use test_app_scene, only: collect_app_scene
  use test_material, only: collect_material
  use test_mfix, only: collect_mfix
  use test_lanczos, only: collect_lanczos
  use test_lanczos_top, only: collect_lanczos_top
  use test_app_mfix, only: collect_app_mfix
  use test_app_material, only: collect_app_material
  use test_recommend, only: collect_recommend
  use test_snapshot, only: collect_snapshot
  use test_app_snapshot, only: collect_app_snapshot
  use test_packing, only: collect_packing
  use test_damping, only: collect_damping
  use test_liggghts, only: collect_liggghts
  use test_liggghts_script, only: collect_liggghts_script
  use test_liggghts_scenes, only: collect_liggghts_scenes
  use test_app_safety, only: collect_app_safety
  use test_structure, only: collect_structure
  use test_monitor, only: collect_monitor
  use test_bonds, only: collect_bonds
  use test_bodies, only: collect_bodies
  use test_covering_lp, only: collect_covering_lp
  use test_sort, only: collect_sort
  implicit none
  integer :: stat, is, total
  character(len=:), allocatable :: suite_name, test_name
  type(testsuite_type), allocatable :: testsuites(:)
  type(unittest_type), allocatable :: tests(:)

  testsuites = [ &
    new_testsuite("spring", collect_spring), &
    new_testsuite("namelist", collect_namelist), &
    new_testsuite("table_io", collect_table_io), &
    new_testsuite("text", collect_text), &
    new_testsuite("harmonic", collect_harmonic), &
    new_testsuite("roots", collect_roots), &
    new_testsuite("stiffness", collect_stiffness), &
    new_testsuite("scene", collect_scene), &
    new_testsuite("interaction", collect_interaction), &
    new_testsuite("damping", collect_damping), &
    new_testsuite("liggghts", collect_liggghts), &
    new_testsuite("liggghts_script", collect_liggghts_script), &
    new_testsuite("liggghts_scenes", collect_liggghts_scenes), &
    new_testsuite("yade", collect_yade), &
    new_testsuite("contact", collect_contact), &
    new_testsuite("cost", collect_cost), &
    new_testsuite("double_double", collect_double_double), &
    new_testsuite("capi", collect_capi), &
    new_testsuite("progress", collect_progress), &
    new_testsuite("deck", collect_deck), &
    new_testsuite("extremes", collect_extremes), &
    new_testsuite("app", collect_app), &
    new_testsuite("app_stiffness", collect_app_stiffness), &
    new_testsuite("app_scene", collect_app_scene), &
    new_testsuite("material", collect_material), &
    new_testsuite("mfix", collect_mfix), &
    new_testsuite("lanczos", collect_lanczos), &
    new_testsuite("lanczos_top", collect_lanczos_top), &
    new_testsuite("app_mfix", collect_app_mfix), &
    new_testsuite("app_material", collect_app_material), &
    new_testsuite("recommend", collect_recommend), &
    new_testsuite("snapshot", collect_snapshot), &
    new_testsuite("app_snapshot", collect_app_snapshot), &
    new_testsuite("packing", collect_packing), &
    new_testsuite("app_safety", collect_app_safety), &
    new_testsuite("structure", collect_structure), &
    new_testsuite("monitor", collect_monitor), &
    new_testsuite("bonds", collect_bonds), &
    new_testsuite("bodies", collect_bodies), &
    new_testsuite("covering_lp", collect_covering_lp), &
    new_testsuite("sort", collect_sort) &
    ]
  stat = 0
  total = 0
  call get_argument(1, suite_name)
  call get_argument(2, test_name)
  if (allocated(suite_name)) then
    is = select_suite(testsuites, suite_name)
    if (is < 1 .or. is > size(testsuites)) then
      write(output_unit, '(a)') "no suite '"//suite_name//"'; available:"
      do is = 1, size(testsuites)
        write(output_unit, '(2x, a)') testsuites(is)%name
      end do
      stop 1, quiet=.true.
    end if
    write(output_unit, '(a)') "# suite "//testsuites(is)%name
    if (allocated(test_name)) then
      call run_selected(testsuites(is)%collect, test_name, output_unit, stat)
      if (stat < 0) stop 1, quiet=.true.
      total = 1
    else
      call run_testsuite(testsuites(is)%collect, output_unit, stat)
      call testsuites(is)%collect(tests)
      total = size(tests)
    end if
  else
    do is = 1, size(testsuites)
      write(output_unit, '(a)') "# suite "//testsuites(is)%name
      call run_testsuite(testsuites(is)%collect, output_unit, stat)
      call testsuites(is)%collect(tests)
      total = total + size(tests)
    end do
  end if
  write(output_unit, '(i0, a, i0, a)') total - stat, " passed, ", stat, " failed"
  if (stat > 0) stop 1, quiet=.true.
end program tester
