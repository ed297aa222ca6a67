# Compiler flags shared by every lockstep target (through lockstep_flags).
add_library(lockstep_flags INTERFACE)
add_library(lockstep::flags ALIAS lockstep_flags)
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  # -ffp-contract=off: FMA contraction is the one value-changing transform that
  # compilers enable by default; the float and double engines must not get it.
  target_compile_options(lockstep_flags INTERFACE
    $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wpedantic -Wshadow -ffp-contract=off>)
  if(LOCKSTEP_WERROR)
    target_compile_options(lockstep_flags INTERFACE $<$<COMPILE_LANGUAGE:CXX>:-Werror>)
  endif()
  if(LOCKSTEP_SANITIZE)
    target_compile_options(lockstep_flags INTERFACE
      $<$<COMPILE_LANGUAGE:CXX>:-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer>)
    target_link_options(lockstep_flags INTERFACE -fsanitize=address,undefined)
  endif()
endif()
install(TARGETS lockstep_flags EXPORT lockstepTargets)
